#100=#3003
#3003=0
#3004=0
#101=#3003+#3004+1
#3003=3
M30
(#3003/#3004 read back 0; a value that would suppress single block, feed hold or the override
 is refused, as fivex does not build the suppression. FANUC only: Syntec refuses its
 #2001-#3100, tests/it/syntec_macro.rs.)
(expect: alarm=PS0115)
