(fivex: --preset table-bc --allow-unbuilt)
G41.2 D1
G40
M30
(expect: status=completed)
