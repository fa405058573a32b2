(fivex: --preset table-bc --dialect syntec --allow-unbuilt)
G43.5 H1 I0 J0 K1.
G49
(Syntec names no rule for I/J/K in the G43.5 block; fivex turns the tool to them on a tool)
(rotation machine only [as FANUC, §2.2.3] and refuses them on a table or mixed one [decision,)
(docs/five-axis.md]: the start block would place the workpiece system on a table it turns.)
(expect: alarm=COR-100)
