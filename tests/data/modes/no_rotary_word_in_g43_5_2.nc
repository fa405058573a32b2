(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.5 H1 C10.
(expect: alarm=COR-158)
