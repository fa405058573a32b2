(fivex: --dialect haas)
G65 A1.
M30
(expect: alarm=313 alarm_line=2)
