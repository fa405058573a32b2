#100=1
#101=[[[[[[1]]]]]]
M30
(expect: alarm=PS0118 alarm_line=2 commons=100:1)
