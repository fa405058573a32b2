#100=SIN[[[[[90]]]]]
M30
(Function brackets count: SIN's own bracket plus four.)
(expect: #100=1 status=completed)
