#!/usr/bin/env python3
"""The README's pictures of a served maze (issue #43): a ghost ahead in a corridor, as the player's
recording (`serve --record-dir`) replays it, and a spectator's screen. A real `mazewalk serve` on
loopback and stock `ssh -tt` clients, each in a pseudo-terminal of 100x30 (COLORTERM=truecolor
sent; the device-attributes questions answered as a terminal would). Each picture is bytes replayed
into the `vt100` emulator (`benches/examples/screen_dump.rs`) and drawn by scripts/screen_png.py:
the spectator's, every byte its terminal got; the ghost's, the player's cast up to its goodbye —
checked to be the very screen the player's terminal showed.

    cargo build --release
    cargo build --release -p mazewalk-bench --example screen_dump
    scripts/serve_pictures.py [OUT_DIR]          # default: docs/images

MAZEWALK=path/to/mazewalk picks another build. Needs openssh-client, python3-pil, fonts-dejavu-core.
"""

import glob
import json
import os
import pty
import random
import shutil
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("MAZEWALK", os.path.join(HERE, "target/release/mazewalk"))
DUMP = os.path.join(HERE, "target/release/examples/screen_dump")
COLS, ROWS = 100, 30


class Client:
    """`ssh -tt USER@127.0.0.1` in a pty: its output kept, device-attributes questions answered."""

    def __init__(self, port, user):
        import fcntl
        import struct
        import termios

        self.master, slave = pty.openpty()
        fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", ROWS, COLS, 0, 0))
        args = ["ssh", "-tt", "-F", "/dev/null", "-p", str(port), "-o", "StrictHostKeyChecking=no",
                "-o", "UserKnownHostsFile=/dev/null", "-o", "LogLevel=ERROR", "-o", "BatchMode=yes",
                "-o", "SetEnv=COLORTERM=truecolor", "-i", "/dev/null", f"{user}@127.0.0.1"]
        env = dict(os.environ, TERM="xterm-256color")
        self.proc = subprocess.Popen(args, stdin=slave, stdout=slave, stderr=slave, env=env,
                                     start_new_session=True)
        os.close(slave)
        self.raw = bytearray()
        self.lock = threading.Lock()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        scanned = 0
        while True:
            try:
                data = os.read(self.master, 65536)
            except OSError:
                return
            if not data:
                return
            with self.lock:
                self.raw += data
                questions = self.raw[max(0, scanned - 2):].count(b"\x1b[c")
                scanned = len(self.raw)
            for _ in range(questions):
                os.write(self.master, b"\x1b[?62;22c")

    def send(self, keys):
        os.write(self.master, keys)

    def wait(self, text, within=20.0):
        deadline = time.time() + within
        while time.time() < deadline:
            with self.lock:
                if text.encode() in self.raw:
                    return
            time.sleep(0.05)
        sys.exit(f"no {text!r} from the server")

    def hold(self, key, seconds):
        """A held key: a press every 40 ms, as a terminal's auto-repeat."""
        for _ in range(int(seconds / 0.04)):
            self.send(key)
            time.sleep(0.04)

    def screen(self):
        with self.lock:
            return dump(bytes(self.raw))

    def picture(self, out):
        picture(self.screen(), out)

    def close(self):
        self.proc.kill()
        self.proc.wait()


def dump(raw):
    """The screen `raw` leaves on a COLSxROWS terminal, every cell with its colours."""
    return subprocess.run([DUMP, f"{COLS}x{ROWS}"], input=raw, capture_output=True, check=True).stdout


def picture(screen, out):
    text = out[:-4] + ".txt"
    with open(text, "wb") as f:
        f.write(screen)
    subprocess.run([sys.executable, os.path.join(HERE, "scripts/screen_png.py"), text, out,
                    f"{COLS}x{ROWS}"], check=True)
    os.remove(text)
    print(out)


def before_goodbye(cast):
    """The bytes of an asciicast's output events before the goodbye (which leaves the alternate
    screen)."""
    with open(cast, encoding="utf-8") as f:
        lines = f.read().splitlines()
    raw = b""
    for line in lines[1:]:
        _, code, data = json.loads(line)
        if code == "o":
            if "\x1b[?1049l" in data:
                break
            raw += data.encode()
    return raw


class Server:
    def __init__(self, work, *args):
        self.port = random.randint(20000, 40000)
        self.proc = subprocess.Popen(
            [BIN, "serve", "--open", "--listen", f"127.0.0.1:{self.port}", "--host-key",
             os.path.join(work, "host_key"), *args],
            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        line = self.proc.stdout.readline().decode()
        if "serving on" not in line:
            sys.exit(f"the server did not start: {line!r}")

    def close(self):
        self.proc.terminate()
        self.proc.wait()


# A corridor east to the exit, with alcoves; and the same without an exit (no leader by distance:
# the spectator follows the first to join).
CORRIDOR = """mazewalk-grid 1
tile 4
facing east

####################
######.#####.#######
#@................E#
####.#####.#####.###
####################
"""


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "docs/images")
    work = tempfile.mkdtemp()
    try:
        maze = os.path.join(work, "corridor.grid")
        with open(maze, "w") as f:
            f.write(CORRIDOR)

        # A ghost ahead: bob walks the corridor to the exit (his run is kept), carol races it.
        casts = os.path.join(work, "casts")
        server = Server(work, "--records", os.path.join(work, "records.sqlite"), "--record-dir", casts, maze)
        bob = Client(server.port, "bob")
        bob.wait("? help")
        for _ in range(400):
            bob.send(b"w")
            time.sleep(0.04)
            if b"You found the exit" in bob.raw:
                break
        bob.wait("Best times here")
        bob.close()
        carol = Client(server.port, "carol")
        carol.wait("? help")
        time.sleep(8.5)  # (the news of bob's finish has gone)
        carol.send(b"g")
        time.sleep(1.6)
        seen = carol.screen()
        carol.send(b"q")
        carol.wait("Thanks for walking.")
        carol.close()
        server.close()
        [cast] = glob.glob(os.path.join(casts, "*-carol.cast"))
        replayed = dump(before_goodbye(cast))
        if replayed != seen:
            sys.exit("carol's cast does not replay to the screen she saw")
        picture(replayed, os.path.join(out, "serve-ghost.png"))

        # A spectator follows alice; bob walks ahead of her in the corridor.
        with open(maze, "w") as f:
            f.write(CORRIDOR.replace("E", "."))
        server = Server(work, "--no-records", maze)
        alice = Client(server.port, "alice")
        alice.wait("? help")
        bob = Client(server.port, "bob")
        bob.wait("? help")
        watch = Client(server.port, "watch")
        watch.wait("watching alice")
        bob.hold(b"w", 1.0)
        alice.hold(b"w", 0.3)
        time.sleep(1.0)
        watch.picture(os.path.join(out, "serve-watch.png"))
        for client in (alice, bob, watch):
            client.close()
        server.close()
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
