(fivex: --preset mixed-bc --allow-unbuilt)
G41.3 D1
(expect: alarm=PS5460)
