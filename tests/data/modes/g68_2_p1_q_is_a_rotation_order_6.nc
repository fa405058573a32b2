(fivex: --preset mill3 --dialect syntec --allow-unbuilt)
G68.2 P1 Q12 X0 Y0 Z0 I0 J0 K0
G69
(twp TWP-02, TV-TWP-09 [FANUC only: Syntec's G68.2 has only the Euler form, its P is COR-002, syn SYN-18])
(expect: alarm=COR-002 alarm_line=2)
