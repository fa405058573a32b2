(fivex: --preset head-bc --allow-unbuilt)
G41.2 D1
G21
(expect: alarm=PS5000)
