"""The sizes of the packets of channel data a paramiko client receives (imported by the clients here).

paramiko hands a channel's data to the channel through the transport's table of handlers; the hook
notes each message's size, then feeds the channel as paramiko would.
"""
import paramiko
from paramiko.message import Message


def count_data_packets(transport):
    """Sizes of the CHANNEL_DATA messages `transport` receives from now on, appended as they arrive."""
    sizes = []

    def counted(chan, m):
        data = m.get_binary()
        sizes.append(len(data))
        again = Message()
        again.add_string(data)
        again.rewind()
        paramiko.Channel._feed(chan, again)

    transport._channel_handler_table = dict(transport._channel_handler_table)
    transport._channel_handler_table[paramiko.common.MSG_CHANNEL_DATA] = counted
    return sizes
