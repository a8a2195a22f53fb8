"""A player that types but never reads, with paramiko (tests/serve_e2e.rs).

Logs in to the mazewalk server on 127.0.0.1:PORT as `deaf` (the server must be --open), asks for a
200x60 pty (COLORTERM=truecolor: the largest frames, so the window fills) and a shell, turns the
walls' textures on (`t`: more colours a frame, which the colour tolerance cannot merge), then for
SECONDS sends a left turn and a blind answer to the flow control's
query every 10 ms, and never reads: paramiko's transport thread keeps reading the socket, but the
channel's window is never reopened, so the server's frames stop on a full window while the keys keep
coming. Then it waits, connected, until killed. Prints `typing` when it starts and `typed N` when done.
"""
import sys
import time

import paramiko

port, seconds = int(sys.argv[1]), float(sys.argv[2])
transport = paramiko.Transport(("127.0.0.1", port))
transport.connect()
transport.auth_none("deaf")
channel = transport.open_session()
channel.set_environment_variable("COLORTERM", "truecolor")
channel.get_pty(term="xterm-256color", width=200, height=60)
channel.invoke_shell()
print("typing", flush=True)
channel.send(b"t")
start, sent = time.time(), 0
while time.time() - start < seconds:
    try:
        channel.send(b"\x1b[D\x1b[?62;22c")
    except (OSError, EOFError, paramiko.SSHException):
        break
    sent += 1
    time.sleep(0.01)
print(f"typed {sent}", flush=True)
time.sleep(60)
