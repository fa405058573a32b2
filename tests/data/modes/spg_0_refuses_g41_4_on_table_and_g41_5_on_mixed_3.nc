(fivex: --preset mixed-bc --allow-unbuilt)
G41.5 D1
(expect: alarm=PS0010)
