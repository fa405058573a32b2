(fivex: --preset mill3 --dialect syntec --allow-unbuilt)
G53.6
(syn SYN-21, TV-19 [Syntec only; H0 also: [I] of the extract])
(expect: alarm=MAR-407)
