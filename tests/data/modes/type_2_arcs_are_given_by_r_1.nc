(fivex: --preset head-bc --allow-unbuilt)
G43.5 H1
G02 X10. Y10. I5. J5. F100
(expect: alarm=PS5421)
