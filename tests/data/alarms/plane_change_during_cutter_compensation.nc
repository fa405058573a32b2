(fivex: --dialect fanuc,syntec)
G17 G41 D1 G01 X10. F100
G18
(Cutter compensation is not built: its first block is refused [`unbuilt.rs`], so this)
(interlock of the compensation is checked with the refusal off until it is built.)
(expect: alarm[fanuc]=PS0010 alarm_line=2 alarm[syntec]=COR-100)
