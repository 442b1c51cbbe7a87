"""A plain Zenoh client (no zros), to show what any Zenoh program sees through `zros router`:
    plain_client.py sub ENDPOINT KEY    print each sample's MessagePack payload
    plain_client.py get ENDPOINT KEY    print each reply's MessagePack payload, then exit
"""
import json
import sys
import time

import msgpack
import zenoh

mode, endpoint, key = sys.argv[1:4]
config = zenoh.Config()
config.insert_json5('mode', '"client"')
config.insert_json5('connect/endpoints', json.dumps([endpoint]))
config.insert_json5('scouting/multicast/enabled', 'false')
with zenoh.open(config) as session:
    if mode == 'get':
        for reply in session.get(key, timeout=5):
            if reply.ok is not None:
                print('reply', msgpack.unpackb(reply.ok.payload.to_bytes()), flush=True)
    else:
        session.declare_subscriber(key, lambda s: print('sample', msgpack.unpackb(s.payload.to_bytes()), flush=True))
        print('subscribed', flush=True)
        while True:
            time.sleep(1)
