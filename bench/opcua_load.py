"""The OPC UA side of the shop-floor load (`fivex-load --opcua --opcua-client "PYTHON bench/opcua_load.py"`):
one subscription per machine under Objects/Machines, each monitoring its X axis's (else its first axis's)
ActualPosition (fivex's `Axes/<letter>/ActualPosition`), for SECONDS after every subscription is
made. Prints one JSON object: subscriptions, data changes, their age at arrival (the client's
clock minus the value's source timestamp, same host), subscriptions that saw no change, and
changes whose source timestamp went backwards.

usage: opcua_load.py ENDPOINT SECONDS   (asyncua from scripts/requirements-test.txt)
"""
import asyncio
import json
import sys
import time

from asyncua import Client, ua

MACHINERY = "http://opcfoundation.org/UA/Machinery/"
FIVEX = "urn:fivex:opcua"


class Handler:
    def __init__(self):
        self.changes = 0
        self.ages = []
        self.backwards = 0
        self.last = None
        self.counting = False

    def datachange_notification(self, node, value, data):
        stamp = data.monitored_item.Value.SourceTimestamp
        if stamp is not None and self.last is not None and stamp < self.last:
            self.backwards += 1
        self.last = stamp
        if self.counting and stamp is not None:
            self.changes += 1
            self.ages.append((time.time() - stamp.timestamp()) * 1000.0)


def percentile(values, p):
    if not values:
        return None
    values = sorted(values)
    return values[min(len(values) - 1, int(p * (len(values) - 1) + 0.5))]


async def main(endpoint, seconds):
    async with Client(endpoint, timeout=30) as client:
        machinery = await client.get_namespace_index(MACHINERY)
        fivex = await client.get_namespace_index(FIVEX)
        machines = await client.nodes.objects.get_child(f"{machinery}:Machines")
        handlers = []
        for machine in await machines.get_children():
            ident = machine.nodeid.Identifier
            axes = await client.get_node(ua.NodeId(f"{ident}/Axes", fivex)).get_children()
            if not axes:
                continue
            x = [a for a in axes if a.nodeid.Identifier.endswith("/X")]
            axis = x[0] if x else sorted(axes, key=lambda n: n.nodeid.Identifier)[0]
            position = client.get_node(ua.NodeId(f"{axis.nodeid.Identifier}/ActualPosition", fivex))
            handler = Handler()
            subscription = await client.create_subscription(100, handler)
            await subscription.subscribe_data_change(position, sampling_interval=100)
            handlers.append(handler)
        for h in handlers:
            h.counting = True
        started = time.time()
        await asyncio.sleep(seconds)
        wall = time.time() - started
        for h in handlers:
            h.counting = False
        ages = [a for h in handlers for a in h.ages]
        changes = sum(h.changes for h in handlers)
        print(json.dumps({
            "subscriptions": len(handlers),
            "data_changes": changes,
            "data_changes_per_s": changes / wall,
            "age_ms": {"p50": percentile(ages, 0.5), "p99": percentile(ages, 0.99), "max": max(ages, default=None)},
            "subscriptions_without_change": sum(1 for h in handlers if h.changes == 0),
            "timestamps_backwards": sum(h.backwards for h in handlers),
        }))


if __name__ == "__main__":
    asyncio.run(main(sys.argv[1], float(sys.argv[2])))
