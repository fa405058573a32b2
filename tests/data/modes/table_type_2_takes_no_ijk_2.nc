(fivex: --preset table-bc --allow-unbuilt)
(Only the G41.6 block itself takes no I/J/K on a table machine: after it they are the tool's direction.)
G41.6 D1
X10. K1.
M30
(expect: status=completed)
