"""A player that hands the channel's window back a byte at a time, with paramiko (tests/serve_e2e.rs).

Logs in to the mazewalk server on 127.0.0.1:PORT as `trickle` (the server must be --open) with a
32 KiB window and packets, asks for a 120x40 pty and a shell, and for SECONDS sends a right turn every
100 ms, each followed by 1,500 window adjusts of one byte each (paramiko's own adjusting turned off).
It reads all the while, answering the flow control's query, and notes the size of every packet of
channel data that arrives. Prints `packets N tiny T frames F bytes B`: T the packets of under 64 bytes
sent once the first 32 KiB were used, F the frames (the queries that end them).
"""
import sys
import threading
import time

import paramiko
from paramiko.message import Message

from packets import count_data_packets

port, seconds = int(sys.argv[1]), float(sys.argv[2])
transport = paramiko.Transport(("127.0.0.1", port))
transport.connect()
transport.auth_none("trickle")
channel = transport.open_session(window_size=32768, max_packet_size=32768)
channel.in_window_threshold = 1 << 40  # paramiko never hands the window back by itself
sizes = count_data_packets(transport)
channel.get_pty(term="xterm-256color", width=120, height=40)
channel.invoke_shell()
frames = [0]
stop = [False]


def drain():
    channel.settimeout(0.2)
    while not stop[0]:
        try:
            data = channel.recv(65536)
        except Exception:
            continue
        if not data:
            break
        queries = data.count(b"\x1b[c")
        frames[0] += queries
        if queries:
            channel.send(b"\x1b[?62;22c" * queries)


reader = threading.Thread(target=drain, daemon=True)
reader.start()
adjust = Message()
adjust.add_byte(bytes([93]))  # SSH_MSG_CHANNEL_WINDOW_ADJUST
adjust.add_int(channel.remote_chanid)
adjust.add_int(1)
end = time.time() + seconds
while time.time() < end:
    channel.send(b"\x1b[C")
    for _ in range(1500):
        transport._send_message(adjust)
    time.sleep(0.1)
stop[0] = True
reader.join(1)
used, tiny = 0, 0
for size in sizes:
    if used >= 32768 and size < 64:
        tiny += 1
    used += size
print(f"packets {len(sizes)} tiny {tiny} frames {frames[0]} bytes {used}", flush=True)
transport.close()
