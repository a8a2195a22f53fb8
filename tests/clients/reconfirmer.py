"""A player that confirms its own session channel again mid-game, with paramiko (serve_attacks.rs).

Logs in to the mazewalk server on 127.0.0.1:PORT as `reconfirm` (the server must be open) with 32 KiB
packets, asks for a 120x40 pty and a shell, reads the first frame, then sends
SSH_MSG_CHANNEL_OPEN_CONFIRMATION for its channel with a packet size of 1 and a window of 2^32-1. For
SECONDS it presses Ctrl-L and answers the flow control's query every 100 ms, counting the packets of
channel data that arrive after the confirmation. Prints `packets N tiny T open O`: T the packets of
under 64 bytes, O 1 if the connection was still open at the end.
"""
import sys
import time

import paramiko
from paramiko.message import Message

from packets import count_data_packets

port, seconds = int(sys.argv[1]), float(sys.argv[2])
transport = paramiko.Transport(("127.0.0.1", port))
transport.connect()
transport.auth_none("reconfirm")
channel = transport.open_session(window_size=1 << 24, max_packet_size=32768)
channel.get_pty(term="xterm-256color", width=120, height=40)
channel.invoke_shell()
channel.settimeout(10)
first = b""
while b"\x1b[c" not in first:
    first += channel.recv(65536)
sizes = count_data_packets(transport)
confirm = Message()
confirm.add_byte(bytes([91]))  # SSH_MSG_CHANNEL_OPEN_CONFIRMATION
confirm.add_int(channel.remote_chanid)
confirm.add_int(channel.chanid)
confirm.add_int(2**32 - 1)
confirm.add_int(1)
transport._send_message(confirm)
channel.settimeout(0.1)
end = time.time() + seconds
while time.time() < end and transport.is_active():
    try:
        channel.send(b"\x0c\x1b[?62;22c")
        channel.recv(65536)
    except Exception:
        pass
    time.sleep(0.1)
tiny = sum(1 for size in sizes if size < 64)
print(f"packets {len(sizes)} tiny {tiny} open {int(transport.is_active())}", flush=True)
transport.close()
