#100=10.6 MOD 3
M30
(Decision: MOD rounds both operands to integers [half away from zero] first…)
(expect: #100=2 status=completed)
