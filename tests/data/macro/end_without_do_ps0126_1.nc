#100=1
END1
M30
(expect: alarm_line=2 status=alarm)
