(fivex: --dialect fanuc,syntec)
G00 Z1.
G83 X0 Y0 Z-1000. R0 Q0.001 F1000.
(One million pecks: stopped at the expansion limit, not after exhausting memory.)
(expect: alarm=FX0003 alarm_line=3)
(skip: limits the pecks before the expansion limit take 4.5 hours of motion: not sampled)
(skip: tip the pecks before the expansion limit take 4.5 hours of motion: not sampled)
