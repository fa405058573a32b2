(fivex: --dialect haas)
#100=#20033 (SETTING 33: NOT MODELLED)
M30
(expect: alarm=503 alarm_line=2)
