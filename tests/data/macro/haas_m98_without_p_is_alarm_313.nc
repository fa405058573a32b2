(fivex: --dialect fanuc,haas)
M98 L2
M30
(expect: alarm[fanuc]=PS0078 alarm[haas]=313 alarm_line=2)
