(fivex: --preset table-bc --allow-unbuilt)
G42.4 D1
(expect: alarm=PS0010)
