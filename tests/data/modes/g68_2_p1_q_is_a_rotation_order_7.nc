(fivex: --preset mill3 --allow-unbuilt)
G68.2 P1 Q111 X0 Y0 Z0 I0 J0 K0
(twp TWP-02, TV-TWP-09 [FANUC only: Syntec's G68.2 has only the Euler form])
(expect: alarm=PS5457)
