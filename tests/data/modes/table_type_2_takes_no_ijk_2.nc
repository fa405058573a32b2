(fivex: --preset table-bc --allow-unbuilt)
G41.6 D1
X10. K1.
(expect: alarm=PS5460)
