%
O0001
#100=5
M30
%
(expect: #100=5 status=completed)
