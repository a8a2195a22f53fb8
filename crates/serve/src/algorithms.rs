//! What the server offers in the SSH handshake (README "Host a maze" lists the same):
//!
//! | kind | offered, most preferred first |
//! |---|---|
//! | key exchange | `mlkem768x25519-sha256`, `curve25519-sha256`, `curve25519-sha256@libssh.org` (plus the `ext-info-s` and `kex-strict-s-v00@openssh.com` markers) |
//! | host key | `ssh-ed25519` (the only host key the server has) |
//! | ciphers | `chacha20-poly1305@openssh.com`, `aes256-gcm@openssh.com`, `aes128-gcm@openssh.com`, `aes256-ctr`, `aes192-ctr`, `aes128-ctr` |
//! | MACs (for the CTR ciphers) | `hmac-sha2-512-etm@openssh.com`, `hmac-sha2-256-etm@openssh.com`, `hmac-sha2-512`, `hmac-sha2-256` |
//! | compression | `none` |
//! | players' key signatures (`server-sig-algs`) | `ssh-ed25519`, `ecdsa-sha2-nistp256/384/521`, `rsa-sha2-512`, `rsa-sha2-256` |
//!
//! Why so few: russh computes the finite-field Diffie-Hellman groups (`diffie-hellman-group14..18`,
//! group exchange) with a bignum library on the async workers, 0.9 s of CPU for group18, while a
//! client can send its half without computing anything: ten such handshakes froze every player
//! (issue #34). The elliptic-curve and lattice exchanges cost well under a millisecond. `ssh-rsa`
//! signatures (RSA with SHA-1) are refused as OpenSSH 8.8 and later refuse them; RSA keys still log
//! in with `rsa-sha2-256` or `-512`, which every OpenSSH since 7.2 uses.

use std::borrow::Cow;

use russh::keys::{Algorithm, EcdsaCurve, HashAlg};
use russh::{Preferred, cipher, compression, kex, mac};

/// The key exchanges offered, then the markers russh keeps in the same list: a server sends only the
/// `*-s` ones, and turns strict key exchange (the Terrapin fix) on when the client asks for it.
const KEX: &[kex::Name] = &[
    kex::MLKEM768X25519_SHA256,
    kex::CURVE25519,
    kex::CURVE25519_PRE_RFC_8731,
    kex::EXTENSION_SUPPORT_AS_CLIENT,
    kex::EXTENSION_SUPPORT_AS_SERVER,
    kex::EXTENSION_OPENSSH_STRICT_KEX_AS_CLIENT,
    kex::EXTENSION_OPENSSH_STRICT_KEX_AS_SERVER,
];

/// Host key algorithms (only those a key of the server can serve are offered) and the signature
/// algorithms players' keys may use (the `server-sig-algs` russh sends). No `ssh-rsa`.
const KEYS: &[Algorithm] = &[
    Algorithm::Ed25519,
    Algorithm::Ecdsa { curve: EcdsaCurve::NistP256 },
    Algorithm::Ecdsa { curve: EcdsaCurve::NistP384 },
    Algorithm::Ecdsa { curve: EcdsaCurve::NistP521 },
    Algorithm::Rsa { hash: Some(HashAlg::Sha512) },
    Algorithm::Rsa { hash: Some(HashAlg::Sha256) },
];

const CIPHERS: &[cipher::Name] = &[
    cipher::CHACHA20_POLY1305,
    cipher::AES_256_GCM,
    cipher::AES_128_GCM,
    cipher::AES_256_CTR,
    cipher::AES_192_CTR,
    cipher::AES_128_CTR,
];

const MACS: &[mac::Name] = &[mac::HMAC_SHA512_ETM, mac::HMAC_SHA256_ETM, mac::HMAC_SHA512, mac::HMAC_SHA256];

/// The algorithms the server offers (see the table above).
#[must_use]
pub(crate) fn preferred() -> Preferred {
    Preferred {
        kex: Cow::Borrowed(KEX),
        key: Cow::Borrowed(KEYS),
        host_key_certificates: Cow::Borrowed(&[]),
        cipher: Cow::Borrowed(CIPHERS),
        mac: Cow::Borrowed(MACS),
        compression: Cow::Borrowed(&[compression::NONE]),
    }
}

/// Whether a player's key signs with `algorithm` in a way the server refuses: `ssh-rsa`, RSA over
/// SHA-1. (russh checks that a signature's algorithm is the one the request named, so refusing the
/// name refuses the signature.)
#[must_use]
pub(crate) fn refused_signature(algorithm: &Algorithm) -> bool {
    matches!(algorithm, Algorithm::Rsa { hash: None })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_cheap_key_exchanges_and_no_sha1_are_offered() {
        let p = preferred();
        let kex: Vec<&str> = p.kex.iter().map(|n| n.as_ref()).collect();
        assert!(kex.iter().all(|n| !n.starts_with("diffie-hellman")), "{kex:?}");
        assert_eq!(&kex[..3], ["mlkem768x25519-sha256", "curve25519-sha256", "curve25519-sha256@libssh.org"]);
        let keys: Vec<String> = p.key.iter().map(ToString::to_string).collect();
        assert!(!keys.iter().any(|k| k == "ssh-rsa"), "{keys:?}");
        assert!(keys.iter().any(|k| k == "rsa-sha2-512") && keys.iter().any(|k| k == "ssh-ed25519"));
        let macs: Vec<&str> = p.mac.iter().map(|n| n.as_ref()).collect();
        assert!(macs.iter().all(|m| m.contains("sha2")), "{macs:?}");
        assert!(refused_signature(&Algorithm::Rsa { hash: None }));
        assert!(!refused_signature(&Algorithm::Rsa { hash: Some(HashAlg::Sha256) }));
        assert!(!refused_signature(&Algorithm::Ed25519));
    }
}
