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
//!
//! A player's RSA key with a modulus over [`MAX_RSA_BITS`] or an exponent over
//! [`MAX_RSA_EXPONENT`] is refused before its signature is checked ([`refused_key`]; red-team pass
//! 4: with `--open`, a client sending an 8192-bit key with e = 2³³−1 and random bytes for a signature
//! cost the server 1.6 ms of CPU a request, on the workers players share). A certificate
//! (`*-cert-v01@openssh.com`) cannot be refused before that: russh checks its CA's signature before
//! asking the server, whatever the algorithms offered, and asks the server with the certificate's
//! own key (the server takes no certificates, so none logs in). What bounds that cost is the number
//! of requests a connection gets answered: [`MAX_ACCEPTED_PROBES`](crate::MAX_ACCEPTED_PROBES)
//! probes accepted, then refusals, 7 at most, one per half second (red-team pass 7: probes were
//! accepted without limit, 1.7 ms of CPU each under an 8192-bit RSA CA).

use std::borrow::Cow;

use russh::keys::ssh_key::public::KeyData;
use russh::keys::{Algorithm, EcdsaCurve, HashAlg, PublicKey};
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

/// The largest RSA modulus of a player's key, bits: `ssh-keygen`'s default is 3072; larger keys are
/// rare, and checking a signature costs the server more the larger the key.
pub const MAX_RSA_BITS: u32 = 4096;

/// The largest RSA public exponent of a player's key: 65537, which every key generator uses. (The
/// `rsa` crate allows up to 2³³−1, which costs more to check.)
pub const MAX_RSA_EXPONENT: u64 = 65537;

/// Whether a player's `key` is refused before its signature is checked: an RSA key past
/// [`MAX_RSA_BITS`] or [`MAX_RSA_EXPONENT`].
#[must_use]
pub(crate) fn refused_key(key: &PublicKey) -> bool {
    match key.key_data() {
        KeyData::Rsa(rsa) => {
            let e = rsa.e().as_positive_bytes().unwrap_or(&[]);
            let e = e.iter().skip_while(|&&b| b == 0).collect::<Vec<_>>();
            let exponent = (e.len() <= 8).then(|| e.iter().fold(0u64, |v, &&b| v << 8 | u64::from(b)));
            rsa.key_size() > MAX_RSA_BITS || exponent.is_none_or(|e| e > MAX_RSA_EXPONENT)
        }
        _ => false,
    }
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

    /// Red-team pass 4, F4: an RSA key of 8192 bits, or with e = 2³³−1, is refused before any
    /// signature check; 2048- to 4096-bit keys with e = 65537 (or 3) are not.
    #[test]
    fn absurd_rsa_keys_are_refused() {
        use russh::keys::ssh_key::Mpint;
        use russh::keys::ssh_key::public::RsaPublicKey;
        let rsa = |bits: usize, e: &[u8]| {
            let mut n = vec![0xc5; bits / 8];
            n[bits / 8 - 1] |= 1;
            let key =
                RsaPublicKey::new(Mpint::from_positive_bytes(e), Mpint::from_positive_bytes(&n)).unwrap();
            PublicKey::new(KeyData::Rsa(key), "")
        };
        let f4 = [0x01, 0x00, 0x01];
        for bits in [2048, 3072, 4096] {
            assert!(!refused_key(&rsa(bits, &f4)), "{bits} bits");
        }
        assert!(!refused_key(&rsa(2048, &[3])));
        assert!(refused_key(&rsa(4104, &f4)), "past 4096 bits");
        assert!(refused_key(&rsa(8192, &f4)));
        assert!(refused_key(&rsa(2048, &[0x01, 0x00, 0x03])), "65539");
        assert!(refused_key(&rsa(2048, &[0x01, 0xff, 0xff, 0xff, 0xff])), "2^33 - 1");
        assert!(refused_key(&rsa(2048, &[0x7f; 12])), "wider than 64 bits");
        let ed = russh::keys::ssh_key::public::Ed25519PublicKey([7; 32]);
        assert!(!refused_key(&PublicKey::new(KeyData::Ed25519(ed), "")), "an ed25519 key");
    }
}
