(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G43.4 H1
G02 X10. Y10. R10. F100
G49
(expect: alarm[fanuc]=PS5421 status[syntec]=completed)
