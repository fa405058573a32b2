(fivex: --preset head-bc --allow-unbuilt)
G41.6 D1
G40
(expect: status=completed)
