"""An action client driven by asyncio, spinning the node from the event loop: two goals at
once, then one more, each awaited."""
import asyncio

import rclpy
from action_tutorials_interfaces.action import Fibonacci
from rclpy.action import ActionClient
from rclpy.node import Node


class AsyncioClient(Node):
    def __init__(self):
        super().__init__('asyncio_client')
        self.client = ActionClient(self, Fibonacci, 'fib')

    async def fib(self, order):
        self.client.wait_for_server()
        goal_handle = await self.client.send_goal_async(Fibonacci.Goal(order=order))
        response = await goal_handle.get_result_async()
        return response.result.sequence


async def spin(node):
    while rclpy.ok():
        rclpy.spin_once(node, timeout_sec=0.01)
        await asyncio.sleep(0.001)


async def run():
    with rclpy.init():
        node = AsyncioClient()
        spinner = asyncio.ensure_future(spin(node))
        both = await asyncio.gather(node.fib(4), node.fib(6))
        node.get_logger().info(f'together: {both}')
        node.get_logger().info(f'then: {await node.fib(3)}')
        spinner.cancel()


if __name__ == '__main__':
    asyncio.run(run())
