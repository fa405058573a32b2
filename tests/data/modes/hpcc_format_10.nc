(fivex: --machine ../../../machines/head-exchange-bc-ac.json --dialect syntec)
G05 P10000 X0 Y0 Z0 A1. B1. C1.
(syn §3.1 COR-107 (i), (vi): six axial directions, three rotary axes - A is not in the mechanism)
(expect: alarm=COR-107 alarm_line=2)
