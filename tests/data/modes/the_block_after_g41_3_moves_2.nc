(fivex: --preset head-bc --allow-unbuilt)
G41.3 D1
G40
(expect: alarm=PS5460)
