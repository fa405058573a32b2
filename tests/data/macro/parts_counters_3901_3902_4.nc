#100=1
(The end of the main program's text is not M30: FANUC reads the end of record, PS5010, and no part is counted.)
(expect: #3901=0 status=alarm alarm=PS5010 alarm_line=3)
