(fivex: --preset table-bc --allow-unbuilt)
G41.2 D1
G01 X10. F100
G40 X0
M30
(expect: status=completed)
