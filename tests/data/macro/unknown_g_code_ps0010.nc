(fivex: --dialect syntec)
G53.3
M30
(G53.3 is a Syntec code, not COR-070; before G68.2 it is refused: COR-100, syn §4.3.3 #1)
(expect: alarm=COR-100 alarm_line=2)
