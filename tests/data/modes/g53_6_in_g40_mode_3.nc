(fivex: --preset mill3 --allow-unbuilt)
G42 D1
G53.6 H1
G40
(FANUC states no G40 rule; its G53.6 is refused outside the tilted plane, as in it: PS5462)
(expect: alarm=PS5462 alarm_line=3)
