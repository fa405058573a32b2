(fivex: --preset head-bc --dialect syntec)
G05 P10000 X0 Y0 Z0
(syn §3.1 COR-107 (iv): geometry axes given, no rotary axis)
(expect: alarm=COR-107 alarm_line=2)
