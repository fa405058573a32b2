(fivex: --preset mill3 --dialect syntec --allow-unbuilt)
G68.2 X0 Y0 Z0 I0 J30. K0
G69
(The plane itself needs no mechanism.)
(expect: status=completed)
