"""A bare Zenoh router (router mode, Zenoh defaults, no zros graph service): `bare_router.py ENDPOINT`.
Stands in for zenohd, to check that zros readers get the graph through any Zenoh router."""
import json
import sys
import time

import zenoh

config = zenoh.Config()
config.insert_json5('mode', '"router"')
config.insert_json5('listen/endpoints', json.dumps([sys.argv[1]]))
config.insert_json5('scouting/multicast/enabled', 'false')
with zenoh.open(config) as session:
    print('router up', flush=True)
    while True:
        time.sleep(1)
