#!/usr/bin/env python3
"""The latency of a cycle start and of an MDI text on a controller whose memory holds ten 8 MiB
programs (the largest fivex stores), and the process's peak memory. Prints one line.

    python3 bench/cycle_start_memory.py ./target/release/fivex 19811 /tmp/x.db
"""
import http.client, json, sys, time, subprocess, os, signal
binary, port, db = sys.argv[1], int(sys.argv[2]), sys.argv[3]
for f in [db, db + '.lock', db + '-wal', db + '-shm']:
    if os.path.exists(f): os.remove(f)
srv = subprocess.Popen([binary, 'serve', '--db', db, '--addr', f'127.0.0.1:{port}'], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
def req(method, path, body=None, ctype='application/json', timeout=600):
    c = http.client.HTTPConnection('127.0.0.1', port, timeout=timeout)
    hd = {}
    if body is not None:
        if not isinstance(body, (bytes, str)): body = json.dumps(body)
        if isinstance(body, str): body = body.encode()
        hd['Content-Type'] = ctype
    c.request(method, path, body=body, headers=hd)
    r = c.getresponse(); d = r.read(); c.close()
    return r.status, d
for _ in range(100):
    try:
        if req('GET', '/healthz')[0] == 200: break
    except Exception: time.sleep(0.1)
A = '/api/v1'
s, d = req('POST', A + '/controllers', {'name': 'big', 'preset': 'mill3'}); cid = json.loads(d)['id']
line = 'G01 X1.234 Y2.345 F1000.\n'
big = line * (8 * 1024 * 1024 // len(line) - 1)
for n in range(1, 11):
    s, d = req('PUT', f'{A}/controllers/{cid}/programs/{n}', big, ctype='text/plain'); assert s in (200, 201), (s, d[:200])
s, d = req('PUT', f'{A}/controllers/{cid}/programs/11', 'G0 X1.\nM30\n', ctype='text/plain'); assert s in (200, 201), (s, d)
t = time.time(); s, d = req('POST', f'{A}/controllers/{cid}/cycle-start', {'program': 11}); t1 = time.time() - t
time.sleep(2)
t = time.time(); s2, d2 = req('POST', f'{A}/controllers/{cid}/mdi', {'text': 'G0 X2.'}); t2 = time.time() - t
time.sleep(2)
rss = int([l for l in open(f'/proc/{srv.pid}/status') if l.startswith('VmHWM')][0].split()[1]) // 1024
print(f'{binary}: cycle start {s} {t1:.2f} s, mdi {s2} {t2:.2f} s, peak RSS {rss} MiB')
srv.send_signal(signal.SIGTERM); srv.wait()
