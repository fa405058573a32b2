(fivex: --preset mill3 --dialect syntec --allow-unbuilt)
G68.3 P1 X0 Y0 Z0
G69
(syn SYN-24, TV-24, §6.2 alarm 154: Pr3001 = 0 [no mechanism: the mill3 model, which)
(Pr3001 = 0 reads to] and G53.1 or G68.3 is COR-154.)
(expect: alarm=COR-154)
