G51 X0 Y0 P-1000
M30
(expect: alarm=PS0142)
