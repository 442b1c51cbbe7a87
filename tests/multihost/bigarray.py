"""A test node for large arrays: `bigarray.py pub COUNT` publishes COUNT 4 MB sensor_msgs/Image on
/big (frame i: stamp.sec i, pixels from a generator seeded with i) and prints
`published i <sha256 of the pixels>`; `bigarray.py sub` prints `got i <sha256>` per image."""
import hashlib
import sys
import time

import numpy as np

import zros
from zros.node import Node

from interfaces.sensor_msgs.msg import Image

SIZE = 4 << 20


def pixels(i: int) -> np.ndarray:
    return np.random.default_rng(i).integers(0, 256, SIZE, dtype=np.uint8)


def main() -> None:
    role = sys.argv[1]
    zros.init([])
    node = Node(f'big_{role}')
    if role == 'pub':
        pub = node.create_publisher(Image, 'big', 10)
        deadline = time.monotonic() + 10
        while pub.get_subscription_count() == 0 and time.monotonic() < deadline:
            time.sleep(0.05)
        time.sleep(0.5)
        for i in range(1, int(sys.argv[2]) + 1):
            msg = Image(height=1024, width=1024, encoding='rgba8', step=4096, data=pixels(i))
            msg.header.stamp.sec = i
            pub.publish(msg)
            print(f'published {i} {hashlib.sha256(msg.data).hexdigest()}', flush=True)
            time.sleep(0.05)
        zros.spin(node)
    node.create_subscription(
        Image, 'big', lambda m: print(f'got {m.header.stamp.sec} {hashlib.sha256(m.data).hexdigest()}', flush=True), 100)
    print('subscribed', flush=True)
    zros.spin(node)


if __name__ == '__main__':
    try:
        main()
    except KeyboardInterrupt:
        pass
