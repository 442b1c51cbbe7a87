"""Another node's parameters: load a parameter file into the parameter blackboard and read
them back, as ROS 2's async parameter client demo does."""
import sys

import rclpy
from rclpy.parameter import Parameter, parameter_dict_from_yaml_file, parameter_value_to_python
from rclpy.parameter_client import AsyncParameterClient


def main():
    with rclpy.init():
        node = rclpy.create_node('blackboard_client')
        client = AsyncParameterClient(node, 'parameter_blackboard')
        if not client.wait_for_services(10.0):
            sys.exit('no parameter_blackboard')
        future = client.set_parameters([Parameter('speed', Parameter.Type.DOUBLE, 0.5)])
        rclpy.spin_until_future_complete(node, future)
        future = client.load_parameter_file(sys.argv[1])
        rclpy.spin_until_future_complete(node, future)
        loaded = parameter_dict_from_yaml_file(sys.argv[1])
        for name, result in zip(loaded, future.result().results):
            node.get_logger().info(f'loaded {name}: {result.successful}')
        names = ['speed'] + list(loaded)
        future = client.get_parameters(names)
        rclpy.spin_until_future_complete(node, future)
        values = [parameter_value_to_python(value) for value in future.result().values]
        node.get_logger().info(f'blackboard: {dict(zip(names, values))}')


if __name__ == '__main__':
    main()
