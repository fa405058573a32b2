"""The OPC UA tests' independent client: Python's asyncua (FreeOpcUa, not async-opcua) drives
fivex's OPC UA server the way an integrator's client would. One command per run, results as
JSON lines on stdout for the Rust side to assert on; it asserts nothing itself.

    opcua_client.py URL SECURITY USER PASSWORD COMMAND ARGS...

SECURITY is `none`, `basic256sha256` or `aes256sha256rsapss` (signed and encrypted, with a
self-signed client certificate made for the run); USER `-` is an anonymous session.
"""

import asyncio
import json
import socket
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

from asyncua import Client, ua
from asyncua.common.events import get_filter_from_event_type
from asyncua.crypto import security_policies
from asyncua.crypto.cert_gen import setup_self_signed_certificate
from cryptography.x509.oid import ExtendedKeyUsageOID

MACHINERY = "http://opcfoundation.org/UA/Machinery/"
MACHINE_TOOL = "http://opcfoundation.org/UA/MachineTool/"
FIVEX = "urn:fivex:opcua"


def out(**record):
    print(json.dumps(record), flush=True)


def status_name(code):
    return ua.status_codes.get_name_and_doc(code)[0]


async def connect(url, security, user, password):
    client = Client(url, timeout=30)
    client.application_uri = "urn:fivex:tests:asyncua"
    if user != "-":
        client.set_user(user)
        client.set_password(password)
    if security != "none":
        policy = {
            "basic256sha256": security_policies.SecurityPolicyBasic256Sha256,
            "aes256sha256rsapss": security_policies.SecurityPolicyAes256Sha256RsaPss,
        }[security]
        directory = Path(tempfile.mkdtemp())
        key, cert = directory / "key.pem", directory / "cert.der"
        await setup_self_signed_certificate(
            key,
            cert,
            client.application_uri,
            socket.gethostname(),
            [ExtendedKeyUsageOID.CLIENT_AUTH],
            {"commonName": "fivex tests"},
        )
        await client.set_security(policy, cert, key, mode=ua.MessageSecurityMode.SignAndEncrypt)
    await client.connect()
    return client


async def machines(client):
    """The Machines folder's machines: {browse name: node}."""
    machinery = await client.get_namespace_index(MACHINERY)
    folder = await client.nodes.objects.get_child([f"{machinery}:Machines"])
    found = {}
    for node in await folder.get_children():
        found[(await node.read_browse_name()).Name] = node
    return found


async def machine(client, name):
    """The machine called `name`, waiting up to 20 s for it (it appears with the observer's
    next round after the controller is created)."""
    deadline = time.monotonic() + 20
    while True:
        found = await machines(client)
        if name in found or time.monotonic() > deadline:
            return found[name]
        await asyncio.sleep(0.1)


async def child(node, *path):
    """The node at `path` below `node`, each step by browse name whatever its namespace."""
    for name in path:
        for c in await node.get_children():
            if (await c.read_browse_name()).Name == name:
                node = c
                break
        else:
            raise KeyError(f"{name} not below {node}")
    return node


async def value(node, *path):
    v = await (await child(node, *path)).read_value()
    if isinstance(v, ua.LocalizedText):
        return v.Text
    return v


async def cmd_browse(client, args):
    """Every machine, once there are COUNT (or after 20 s): its type, identification, channel,
    program state and axis positions."""
    count = int(args[0])
    deadline = time.monotonic() + 20
    while len(found := await machines(client)) < count and time.monotonic() < deadline:
        await asyncio.sleep(0.1)
    namespaces = await client.get_namespace_array()
    for name, node in found.items():
        type_id = await node.read_type_definition()
        type_name = (await client.get_node(type_id).read_browse_name()).Name
        axes = {}
        for axis in await (await child(node, "Axes")).get_children():
            letter = (await axis.read_browse_name()).Name
            axes[letter] = await value(axis, "ActualPosition")
        units = await value(node, "Axes", "X", "ActualPosition", "EngineeringUnits")
        out(
            machine=name,
            node=node.nodeid.to_string(),
            type=type_name,
            type_namespace=namespaces[type_id.NamespaceIndex],
            manufacturer=await value(node, "Identification", "Manufacturer"),
            model=await value(node, "Identification", "Model"),
            serial=await value(node, "Identification", "SerialNumber"),
            operation_mode=await value(node, "Monitoring", "MachineTool", "OperationMode"),
            channel_state=await value(node, "Monitoring", "Channel1", "ChannelState"),
            channel_mode=await value(node, "Monitoring", "Channel1", "ChannelMode"),
            feed_override=await value(node, "Monitoring", "Channel1", "FeedOverride"),
            feed_override_range=[
                (r := await value(node, "Monitoring", "Channel1", "FeedOverride", "EURange")).Low,
                r.High,
            ],
            is_rotating=await value(node, "Monitoring", "Spindle", "IsRotating"),
            spindle_override=await value(node, "Monitoring", "Spindle", "Override"),
            spindle_override_range=[
                (r := await value(node, "Monitoring", "Spindle", "Override", "EURange")).Low,
                r.High,
            ],
            program=await value(node, "Production", "ActiveProgram", "Name"),
            program_state=await value(node, "Production", "ActiveProgram", "State", "CurrentState"),
            x_unit=units.DisplayName.Text,
            axes=axes,
        )


async def cmd_positions(client, args):
    """The axes of machine NAME, read until they equal EXPECTED (JSON, per axis) within 1e-9 or
    20 s passed; the last reading."""
    name, expected = args[0], json.loads(args[1])
    deadline = time.monotonic() + 20
    while True:
        node = await machine(client, name)
        axes = {}
        for axis in await (await child(node, "Axes")).get_children():
            axes[(await axis.read_browse_name()).Name] = await value(axis, "ActualPosition")
        same = axes.keys() == expected.keys() and all(abs(axes[a] - expected[a]) <= 1e-9 for a in axes)
        if same or time.monotonic() > deadline:
            out(axes=axes)
            return
        await asyncio.sleep(0.1)


async def cmd_names(client, args):
    """The machines' names once they are exactly NAMES (JSON), or after 20 s."""
    wanted = sorted(json.loads(args[0]))
    deadline = time.monotonic() + 20
    while True:
        names = sorted((await machines(client)).keys())
        if names == wanted or time.monotonic() > deadline:
            out(names=names)
            return
        await asyncio.sleep(0.1)


class Collector:
    def __init__(self, labels):
        self.labels = labels
        self.events = []

    def datachange_notification(self, node, val, data):
        # async-opcua also sends an event item a first data value, BadWaitingForInitialData.
        name = self.labels.get(node.nodeid.to_string())
        if name is not None:
            out(kind="data", name=name, value=val, at=time.monotonic())

    def event_notification(self, event):
        self.events.append(event)
        out(
            kind="event",
            message=event.Message.Text,
            severity=event.Severity,
            source_name=event.SourceName,
            source_node=event.SourceNode.to_string(),
            identifier=getattr(event, "Identifier", None),
            at=time.monotonic(),
        )


def rest(base, method, path, body=None):
    request = urllib.request.Request(base + path, method=method)
    data = None
    if body is not None:
        data = json.dumps(body).encode()
        request.add_header("content-type", "application/json")
    with urllib.request.urlopen(request, data=data, timeout=30) as response:
        return json.loads(response.read() or b"null")


async def subscribe_alarms(client, subscription, node):
    """Subscribes `subscription` to the alarm events of machine `node`."""
    fivex = await client.get_namespace_index(FIVEX)
    event_type = client.get_node(ua.NodeId("ControllerAlarmEventType", fivex))
    # The fields of the type and its supertypes, and the type by OfType: async-opcua 0.19
    # compares no NodeIds in InList, asyncua's own where clause.
    evfilter = await get_filter_from_event_type([event_type])
    of_type = ua.ContentFilterElement(
        FilterOperator_=ua.FilterOperator.OfType,
        FilterOperands=[ua.LiteralOperand(Value=ua.Variant(event_type.nodeid))],
    )
    evfilter.WhereClause = ua.ContentFilter(Elements=[of_type])
    await subscription.subscribe_events(node, event_type, evfilter=evfilter)


async def cmd_watch(client, args):
    """Subscribes to machine NAME's X position and channel state and to its events, then over
    the REST API at BASE (the controller ID): runs program 1 for SECONDS, resets, runs program 2
    (which raises an alarm) and waits up to 20 s for the alarm's event."""
    name, base, cid, seconds = args[0], args[1], args[2], float(args[3])
    node = await machine(client, name)
    x = await child(node, "Axes", "X", "ActualPosition")
    state = await child(node, "Monitoring", "Channel1", "ChannelState")
    collector = Collector({x.nodeid.to_string(): "x", state.nodeid.to_string(): "channel_state"})
    subscription = await client.create_subscription(100, collector)
    await subscription.subscribe_data_change([x, state])
    await subscribe_alarms(client, subscription, node)
    out(kind="subscribed", at=time.monotonic())
    rest(base, "POST", f"/api/v1/controllers/{cid}/cycle-start", {"program": 1})
    await asyncio.sleep(seconds)
    rest(base, "POST", f"/api/v1/controllers/{cid}/reset")
    deadline = time.monotonic() + 20
    while rest(base, "GET", f"/api/v1/controllers/{cid}")["run_state"] != "idle":
        if time.monotonic() > deadline:
            break
        await asyncio.sleep(0.1)
    rest(base, "POST", f"/api/v1/controllers/{cid}/cycle-start", {"program": 2})
    deadline = time.monotonic() + 20
    while not collector.events and time.monotonic() < deadline:
        await asyncio.sleep(0.1)
    await subscription.delete()


async def cmd_quick(client, args):
    """Subscribes to machine NAME's events, then over the REST API at BASE (the controller ID)
    runs program PROGRAM, resets it as soon as the REST status shows its alarm (well within an
    observer period) and collects the events for SECONDS more."""
    name, base, cid, program, seconds = args[0], args[1], args[2], int(args[3]), float(args[4])
    node = await machine(client, name)
    collector = Collector({})
    subscription = await client.create_subscription(100, collector)
    await subscribe_alarms(client, subscription, node)
    rest(base, "POST", f"/api/v1/controllers/{cid}/cycle-start", {"program": program})
    deadline = time.monotonic() + 10
    while rest(base, "GET", f"/api/v1/controllers/{cid}")["run_state"] != "alarm":
        if time.monotonic() > deadline:
            break
        await asyncio.sleep(0.005)
    rest(base, "POST", f"/api/v1/controllers/{cid}/reset")
    out(kind="reset", at=time.monotonic())
    await asyncio.sleep(seconds)
    await subscription.delete()


async def cmd_call(client, args):
    """Calls Panel/METHOD of machine NAME: the status's name."""
    name, method = args[0], args[1]
    panel = await child(await machine(client, name), "Panel")
    fivex = await client.get_namespace_index(FIVEX)
    try:
        await panel.call_method(f"{fivex}:{method}")
        out(status="Good")
    except ua.UaStatusCodeError as e:
        out(status=status_name(e.code))


async def cmd_call_id(client, args):
    """Calls Panel/METHOD of the controller ID by node id, without browsing for it (a deleted
    controller's machine is gone): the status's name."""
    cid, method = args[0], args[1]
    fivex = await client.get_namespace_index(FIVEX)
    request = ua.CallMethodRequest()
    request.ObjectId = ua.NodeId(f"{cid}/Panel", fivex)
    request.MethodId = ua.NodeId(f"{cid}/Panel/{method}", fivex)
    result = (await client.uaclient.call([request]))[0]
    out(status=status_name(result.StatusCode.value))


COMMANDS = {
    "browse": cmd_browse,
    "positions": cmd_positions,
    "names": cmd_names,
    "watch": cmd_watch,
    "quick": cmd_quick,
    "call": cmd_call,
    "call-id": cmd_call_id,
}


async def main():
    url, security, user, password, command, *args = sys.argv[1:]
    try:
        client = await connect(url, security, user, password)
    except ua.UaStatusCodeError as e:
        out(refused=status_name(e.code))
        return
    try:
        await COMMANDS[command](client, args)
    finally:
        await client.disconnect()


asyncio.run(main())
