(fivex: --preset head-bc --allow-unbuilt)
G02 X10. Y10. R10. F100
G43.9 H1
(expect: alarm=PS5421)
