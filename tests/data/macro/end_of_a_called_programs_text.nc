(fivex: --dialect fanuc,syntec,haas)
M98 P20
#101=1
M30
O0020
#100=1
(A called program's text ends without M99: a FANUC reads the end of record there and stops,)
(PS5010 at its text's last line, these comments being its blocks; the caller's #101=1 never runs;)
(fivex returned and ran on. Syntec and)
(Haas return to the caller: no source of theirs says otherwise.)
(expect: alarm[fanuc]=PS5010 alarm_line[fanuc]=12 commons[fanuc]=100:1)
(expect: status[syntec]=completed commons[syntec]=100:1,101:1 status[haas]=completed commons[haas]=100:1,101:1)
