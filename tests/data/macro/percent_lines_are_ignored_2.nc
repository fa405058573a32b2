%  TAPE START
#100=6
M30
%
(`%` with text after it is still a tape mark line.)
(expect: #100=6 status=completed)
