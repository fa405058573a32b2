(fivex: --preset head-bc --allow-unbuilt)
G54.4 P1
G43.4 H1
(twp WSE-11, TV-WSE-19b [RCM = 0])
(expect: alarm=PS5421)
