(fivex: --dialect haas)
G20
G65 P2000 I1 J2 K3 I4 J5 K6
M30
O2000
#100=#4
#101=#5
#102=#6
#103=#7
#104=#8
#105=#9
M99
(The mill manual's example: two I, J, K sets without decimal points set #4 to #9 to .0001 to .0006 in inch.)
(expect: #100=0.0001~1e-12 #101=0.0002~1e-12 #102=0.0003~1e-12 #103=0.0004~1e-12 #104=0.0005~1e-12 #105=0.0006~1e-12 status=completed)
