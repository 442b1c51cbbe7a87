"""A test node: `seqnode.py pub NAME [HZ]` publishes 1, 2, 3, ... on /seq (reliable, depth 1000),
each with its wall time of sending; `seqnode.py sub NAME` prints every number it receives as
`got N`, then `at T delay MS`: when it arrived, and how long it took (the hosts are network
namespaces of one machine, so they share one clock and the delay is the one-way latency).
SEQ_TOPIC names another topic, for a second stream the other way."""
import os
import sys
import time

import zros
from zros.node import Node

from interfaces.std_msgs.msg import String


def received(msg: String) -> None:
    now = time.time()
    count, _, sent = msg.data.partition(' ')
    print(f'got {count}\nat {now:.6f} delay {(now - float(sent or now)) * 1e3:.2f}', flush=True)


def main() -> None:
    role, name = sys.argv[1], sys.argv[2]
    topic = os.environ.get('SEQ_TOPIC', 'seq')
    zros.init([])
    node = Node(name)
    if role == 'pub':
        period = 1.0 / float(sys.argv[3]) if len(sys.argv) > 3 else 0.05
        pub = node.create_publisher(String, topic, 1000)
        count = 0
        while True:
            count += 1
            pub.publish(String(data=f'{count} {time.time():.6f}'))
            print(f'published {count}', flush=True)
            time.sleep(period)
    node.create_subscription(String, topic, received, 1000)
    print('subscribed', flush=True)
    zros.spin(node)


if __name__ == '__main__':
    try:
        main()
    except KeyboardInterrupt:
        pass
