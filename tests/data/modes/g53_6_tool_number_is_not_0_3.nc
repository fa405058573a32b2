(fivex: --preset mill3 --allow-unbuilt)
G53.6
G53.6 H0
(FANUC states no tool number rule; its G53.6 is refused outside the tilted plane, as in it: PS5462)
(expect: alarm=PS5462 alarm_line=2)
