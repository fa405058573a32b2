G68 X0 Y0 R90.
G28 X10. Y0
M30
(FANUC: G27-G30 and G52-G59/G92 must not be specified in rotation mode; cancel G68 first)
(expect: alarm=FX0012 alarm_line=2)
