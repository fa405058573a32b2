(fivex: --preset head-bc --allow-unbuilt)
G41.3 D1 M08
(expect: alarm=PS5460)
