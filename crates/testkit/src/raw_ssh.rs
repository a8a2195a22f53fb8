//! A hand-made SSH client for attacks on the server (tests and `examples/attacks.rs`): the packets
//! before the key exchange are plain (RFC 4253 §6), so a client that does no cryptography at all can
//! offer what it likes and send its half of a Diffie-Hellman exchange without computing it. Blocking
//! I/O on `std::net`, every read with a timeout.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::{Duration, Instant};

/// SSH_MSG_KEXINIT.
const KEXINIT: u8 = 20;
/// SSH_MSG_KEXDH_INIT.
const KEXDH_INIT: u8 = 30;

/// `bytes` as an SSH string (length, then the bytes).
fn string(out: &mut Vec<u8>, bytes: &[u8]) {
    out.extend((bytes.len() as u32).to_be_bytes());
    out.extend(bytes);
}

/// A binary packet around `payload`, unencrypted: length, padding length, payload, 4 to 11 bytes of
/// padding to a multiple of 8, no MAC.
#[must_use]
pub fn packet(payload: &[u8]) -> Vec<u8> {
    let padding = 4 + (8 - (4 + 1 + payload.len() + 4) % 8) % 8;
    let mut out = ((1 + payload.len() + padding) as u32).to_be_bytes().to_vec();
    out.push(padding as u8);
    out.extend(payload);
    out.extend(std::iter::repeat_n(0u8, padding));
    out
}

/// A KEXINIT offering `kex` for the key exchange (comma-separated) and common choices for the rest.
#[must_use]
pub fn kexinit(kex: &str) -> Vec<u8> {
    let mut payload = vec![KEXINIT];
    payload.extend([7u8; 16]); // the cookie
    for list in [
        kex,
        "ssh-ed25519",
        "aes128-ctr",
        "aes128-ctr",
        "hmac-sha2-256",
        "hmac-sha2-256",
        "none",
        "none",
        "",
        "",
    ] {
        string(&mut payload, list.as_bytes());
    }
    payload.push(0); // no guessed packet follows
    payload.extend(0u32.to_be_bytes());
    packet(&payload)
}

/// A KEXINIT whose key exchange list is `names` junk names (about 15 KB for 600): what a client that
/// wants the server's log to grow sends (issue #34).
#[must_use]
pub fn junk_kexinit(names: usize) -> Vec<u8> {
    let list: Vec<String> = (0..names).map(|i| format!("junk-{i:04}-kex@example.com")).collect();
    kexinit(&list.join(","))
}

/// A KEXDH_INIT with an `e` of `bits` bits that no one computed (its top bit set, below any safe
/// prime of that size): the server computes both its own modular exponentiations on it.
#[must_use]
pub fn kexdh_init(bits: usize, seed: u64) -> Vec<u8> {
    let mut e = vec![0u8; bits / 8];
    let mut x = seed | 1;
    for b in &mut e {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        *b = x as u8;
    }
    e[0] = 0x40 | (e[0] & 0x3f); // positive, below 2^(bits-1): within the group
    let mut payload = vec![KEXDH_INIT];
    string(&mut payload, &e);
    packet(&payload)
}

/// A connection from `from` (any loopback address works on Linux: 127.0.0.2 is another address
/// as the server counts them) to `to`, with our identification line sent.
///
/// # Errors
/// The connection cannot be made.
pub fn connect(from: Option<std::net::IpAddr>, to: SocketAddr) -> std::io::Result<TcpStream> {
    let stream = match from {
        Some(ip) => {
            let socket = socket2::Socket::new(socket2::Domain::for_address(to), socket2::Type::STREAM, None)?;
            socket.bind(&SocketAddr::new(ip, 0).into())?;
            socket.connect_timeout(&to.into(), Duration::from_secs(5))?;
            TcpStream::from(socket)
        }
        None => TcpStream::connect_timeout(&to, Duration::from_secs(5))?,
    };
    stream.set_nodelay(true)?;
    (&stream).write_all(b"SSH-2.0-raw_attacker\r\n")?;
    Ok(stream)
}

/// Reads (and drops) what the server sends until it closes the connection; returns how long that
/// took, or `None` if it was still open after `within`.
pub fn until_closed(stream: &mut TcpStream, within: Duration) -> Option<Duration> {
    let start = Instant::now();
    let mut buf = [0u8; 4096];
    loop {
        let left = within.checked_sub(start.elapsed())?;
        stream.set_read_timeout(Some(left.max(Duration::from_millis(1)))).ok()?;
        match stream.read(&mut buf) {
            Ok(0) => return Some(start.elapsed()),
            Ok(_) => {}
            Err(e) if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => {
                return None;
            }
            Err(_) => return Some(start.elapsed()), // reset: closed too
        }
    }
}

/// Reads what the server sends until it closes the connection or sends a packet other than its
/// KEXINIT (its answer to ours: a key exchange reply, a disconnect); returns how long that took, or
/// `None` if neither came within `within`.
pub fn until_answered(stream: &mut TcpStream, within: Duration) -> Option<Duration> {
    let start = Instant::now();
    let mut got: Vec<u8> = Vec::new();
    let mut buf = [0u8; 4096];
    loop {
        // the identification line, then packets: [length u32][padding u8][type u8]…
        if let Some(end) = got.windows(2).position(|w| w == b"\r\n") {
            let mut at = end + 2;
            while got.len() >= at + 6 {
                let len = u32::from_be_bytes([got[at], got[at + 1], got[at + 2], got[at + 3]]) as usize;
                if got[at + 5] != KEXINIT {
                    return Some(start.elapsed());
                }
                at += 4 + len;
            }
        }
        let left = within.checked_sub(start.elapsed())?;
        stream.set_read_timeout(Some(left.max(Duration::from_millis(1)))).ok()?;
        match stream.read(&mut buf) {
            Ok(0) => return Some(start.elapsed()),
            Ok(n) => got.extend_from_slice(&buf[..n]),
            Err(e) if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => {
                return None;
            }
            Err(_) => return Some(start.elapsed()),
        }
    }
}
