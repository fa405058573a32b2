#!/usr/bin/env python3
"""Acknowledged writes per second through `fivex serve` on a database (SQLite file or
PostgreSQL URL): creates 10 controllers, then stores N programs and N retained variables
round-robin over one keep-alive connection, and reads each back once. Prints one line.

    python3 bench/db_writes.py ./target/release/fivex /tmp/x.db [N]
    python3 bench/db_writes.py ./target/release/fivex postgres://fivex@127.0.0.1:5432/fivex [N]
"""
import http.client
import json
import re
import socket
import subprocess
import sys
import threading
import time

fivex, db = sys.argv[1], sys.argv[2]
n = int(sys.argv[3]) if len(sys.argv) > 3 else 2000
sock = socket.socket()
sock.bind(("127.0.0.1", 0))
port = sock.getsockname()[1]
sock.close()
server = subprocess.Popen([fivex, "serve", "--db", db, "--addr", f"127.0.0.1:{port}"],
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
try:
    for line in server.stderr:
        if "listening on" in line:
            break
    # The service logs every request: read on, or it blocks on a full pipe.
    threading.Thread(target=lambda: [None for _ in server.stderr], daemon=True).start()
    conn = http.client.HTTPConnection("127.0.0.1", port)

    def call(method, path, body=None, ctype="application/json"):
        conn.request(method, path, body=body, headers={"content-type": ctype} if body is not None else {})
        reply = conn.getresponse()
        data = reply.read()
        assert reply.status < 300, (method, path, reply.status, data)
        return data

    ids = [json.loads(call("POST", "/api/v1/controllers", json.dumps({"name": f"b{i}", "preset": "mill3"})))["id"]
           for i in range(10)]
    started = time.perf_counter()
    for k in range(n):
        c = ids[k % 10]
        call("PUT", f"/api/v1/controllers/{c}/programs/{1 + k % 50}", f"O{1 + k % 50:04}\n#100={k}\nM30\n", "text/plain")
        call("PUT", f"/api/v1/controllers/{c}/variables/{500 + k % 100}", json.dumps({"value": k}))
    writes = time.perf_counter() - started
    started = time.perf_counter()
    for k in range(n):
        c = ids[k % 10]
        call("GET", f"/api/v1/controllers/{c}/variables/{500 + k % 100}")
    reads = time.perf_counter() - started
    shown = re.sub(r"//([^:@/]+):[^@]*@", r"//\1:***@", db)
    print(f"{shown}: {2 * n / writes:.0f} writes/s, {n / reads:.0f} reads/s ({2 * n} writes, {n} reads)")
finally:
    server.terminate()
    server.wait()
