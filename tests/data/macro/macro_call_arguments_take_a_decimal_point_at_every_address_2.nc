(fivex: --dialect fanuc,syntec)
M0.070
(Outside a call an M with a fraction is still no M code.)
(expect: alarm[fanuc]=PS0009 alarm[syntec]=COR-002)
