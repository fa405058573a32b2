(fivex: --preset head-bc --dialect fanuc,syntec)
G05 P1
(syn §3.1 COR-107 (i): G05 P is 10000 or 0; FANUC: high-speed cycles are not built)
(expect: alarm[fanuc]=PS0010 alarm[syntec]=COR-107 alarm_line=2)
