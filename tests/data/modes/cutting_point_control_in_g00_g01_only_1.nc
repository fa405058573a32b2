(fivex: --preset head-bc --allow-unbuilt)
G43.8 H1
G02 X10. Y10. R10. F100
(tcp TCP-41, TV-67 [alarm not named: PS5421, decision; FANUC only])
(expect: alarm=PS5421)
