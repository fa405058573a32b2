(fivex: --dialect fanuc,haas)
G21 F12
#100=#4109
G20 F12
#101=#4109
F12.
#102=#4109
M30
(Haas Setting 77 at its default: F12 is 0.012 mm/min in G21 and 0.0012 in/min in G20; FANUC
 reads 12 either way. With a point F12. is 12 in both. #4109 reads F in the input unit: in/min
 under G20, so F#4109 gives the same feed again.)
(expect: #100[fanuc]=12 #100[haas]=0.012~1e-12 #101[fanuc]=12~1e-9 #101[haas]=0.0012~1e-12 #102=12~1e-9 status=completed)
