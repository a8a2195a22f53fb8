//! Who may hold a connection open: the server's slots, pure (ids and addresses in, verdicts out; time
//! as seconds). Issue #34 found two ways to lock every player out: connections still in the handshake
//! counted against `--max-players`, and addresses were counted one by one, so one IPv6 /64 — the
//! smallest block a home or a cloud machine gets — was billions of addresses.
//!
//! - **Players and handshakes apart.** A connection starts as a *handshake* (key exchange and
//!   authentication), one of at most [`Limits::max_handshakes`]; it becomes a *player* when it logs
//!   in ([`Slots::promote`]), one of at most [`Limits::max_players`]. Handshakes never take a player's
//!   slot, so a flood of them cannot push out anyone in the game.
//! - **No lockout by idle handshakes** (issue #40). A handshake that has not exchanged keys within
//!   [`Limits::kex_timeout`] is closed. When every handshake slot is taken, a newcomer is never
//!   refused: it takes the slot of the handshake that has gone longest without progress (since it
//!   connected, exchanged keys or asked to log in: [`Slots::progress`]), whichever address holds it.
//!   A client that says its version and waits is the first pushed out; a player's client, whose key
//!   exchange takes milliseconds, moves on before its turn comes. Attackers opening `R` connections
//!   a second into `N` slots leave each handshake `N / R` seconds between steps (256 ms at 500 a
//!   second into the default 128), whatever number of addresses they use.
//! - **Spectators apart too.** A connection that logs in as `watch` becomes a *spectator*
//!   ([`Role::Spectator`]), one of at most [`Limits::max_spectators`]: spectators never take a
//!   player's slot, nor players a spectator's. A newcomer is refused before its handshake only when
//!   both are full (it may be either) and it would push out neither (below); otherwise a player
//!   finding the players full, or a spectator the spectators, is refused when it logs in unless it
//!   pushes one out. One address group holds at most [`Limits::max_spectators_per_address`] of the
//!   spectators' places.
//! - **A full server shares its places fairly** (red-team pass 4: 16 addresses held every player's
//!   place, and 4 every spectator's, for good). A newcomer finding every player's (or spectator's)
//!   place taken pushes out the player (spectator) of the address holding the most places that
//!   pressed no key for the longest, where that address holds at least two more than the newcomer's
//!   ([`fair_push_out`]); otherwise it is refused as before. So a few addresses holding everything
//!   give way, one place at a time, to anyone from elsewhere, and addresses holding one each (an
//!   even share) keep theirs. Spectators have no idle timeout: a screen on a wall presses no key by
//!   design, and a timeout would cut it when nobody else wants the place; being pushed out frees a
//!   place exactly when someone does.
//! - **Address groups.** [`address_group`]: an IPv4 address, or an IPv6 address's /64. Each group
//!   has at most [`Limits::max_per_address`] connections of both kinds, and opens new ones at most
//!   [`Limits::connect_rate`] a second after a burst of twice that many. A full server's fair share
//!   counts IPv6 places by /48 first, then by /56, then by /64 ([`address_prefixes`]): a home gets a
//!   /56 or a /48 (RIPE-690), so one customer's thousands of /64s count as one holder. IPv4 places
//!   count by /24 first, then by address: the smallest block routed on the internet, where one
//!   host's rented addresses usually sit, so 32 addresses of one /24 holding every place give way to
//!   a newcomer from another /24 (the caps stay per address: a campus's many addresses keep theirs).

use std::collections::{BTreeMap, HashMap};
use std::net::{IpAddr, Ipv4Addr, Ipv6Addr};

use super::limits::{Limits, RateLimit};

/// The group an address is counted in: an IPv4 address (also when written as an IPv4-mapped IPv6
/// address, as a dual-stack listener sees it), or the /64 an IPv6 address is in.
#[must_use]
pub(crate) fn address_group(ip: IpAddr) -> IpAddr {
    match ip {
        IpAddr::V4(_) => ip,
        IpAddr::V6(v6) => match v6.to_ipv4_mapped() {
            Some(v4) => IpAddr::V4(v4),
            None => IpAddr::V6(Ipv6Addr::from(u128::from(v6) & (u128::MAX << 64))),
        },
    }
}

/// The prefixes an address is counted in when a full server shares its places ([`fair_push_out`]),
/// widest first: an IPv6 address's /48 (a site), /56 (a home) and /64 ([`address_group`]); an IPv4
/// address's (also IPv4-mapped) /24 twice, then the address itself.
#[must_use]
pub fn address_prefixes(ip: IpAddr) -> [IpAddr; 3] {
    match address_group(ip) {
        IpAddr::V6(v6) => {
            let bits = u128::from(v6);
            [48, 56, 64].map(|len| IpAddr::V6(Ipv6Addr::from(bits & (u128::MAX << (128 - len)))))
        }
        IpAddr::V4(v4) => {
            let block = IpAddr::V4(Ipv4Addr::from(u32::from(v4) & !0xFF));
            [block, block, IpAddr::V4(v4)]
        }
    }
}

/// Which of the places `held` (each holder's address, and its turn: of a group's places, the one
/// with the lowest goes first) a newcomer from `newcomer` pushes out when all are taken, if any.
///
/// The holders are compared by the places their /48 holds, then their /56, then their /64
/// ([`address_prefixes`]; an IPv4 address's /24, then the address): the heaviest gives way, where it holds
/// at least two more than the newcomer's at the first level the two differ (after the swap the
/// newcomer's holds no more than it does, so two groups never take a place back and forth). Never
/// one of the newcomer's own /64 (IPv4 address). `None`: the newcomer is refused. O(places).
#[must_use]
pub fn fair_push_out(held: &[(IpAddr, f64)], newcomer: IpAddr) -> Option<usize> {
    let prefixes: Vec<[IpAddr; 3]> = held.iter().map(|&(ip, _)| address_prefixes(ip)).collect();
    let mut counts: HashMap<(usize, IpAddr), usize> = HashMap::new();
    for (level, prefix) in prefixes.iter().flat_map(|p| p.iter().copied().enumerate()) {
        *counts.entry((level, prefix)).or_default() += 1; // (a /48 and a /56 may read alike: the level keys them)
    }
    let count = |level: usize, prefix: IpAddr| counts.get(&(level, prefix)).copied().unwrap_or(0);
    let weight = |p: &[IpAddr; 3]| [count(0, p[0]), count(1, p[1]), count(2, p[2])];
    let victim = (0..held.len()).max_by(|&a, &b| {
        weight(&prefixes[a]).cmp(&weight(&prefixes[b])).then(held[b].1.total_cmp(&held[a].1))
    })?;
    let (theirs, mine) = (prefixes[victim], address_prefixes(newcomer));
    let level = (0..3).find(|&level| theirs[level] != mine[level])?;
    (count(level, theirs[level]) >= count(level, mine[level]) + 2).then_some(victim)
}

/// A connection's id, in the order they came (so the smallest is the oldest).
pub(crate) type ConnId = u64;

/// Places by prefix level (0 to 2) and prefix ([`address_prefixes`]), as [`fair_push_out`] counts
/// them; a prefix with none is forgotten.
#[derive(Clone, Debug, Default)]
struct PrefixCounts(HashMap<(usize, IpAddr), usize>);

impl PrefixCounts {
    fn add(&mut self, prefixes: &[IpAddr; 3]) {
        for (level, &prefix) in prefixes.iter().enumerate() {
            *self.0.entry((level, prefix)).or_default() += 1;
        }
    }

    fn remove(&mut self, prefixes: &[IpAddr; 3]) {
        for (level, &prefix) in prefixes.iter().enumerate() {
            if let std::collections::hash_map::Entry::Occupied(mut n) = self.0.entry((level, prefix)) {
                *n.get_mut() -= 1;
                if *n.get() == 0 {
                    n.remove();
                }
            }
        }
    }

    fn count(&self, level: usize, prefix: IpAddr) -> usize {
        self.0.get(&(level, prefix)).copied().unwrap_or(0)
    }

    /// A holder's weight: the places of its prefixes, widest first.
    fn weight(&self, p: &[IpAddr; 3]) -> [usize; 3] {
        [self.count(0, p[0]), self.count(1, p[1]), self.count(2, p[2])]
    }
}

/// Why a connection gets no slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Refusal {
    /// `--max-players`, reached.
    Full(usize),
    /// `--max-spectators`, reached.
    Spectators(usize),
    /// Both reached (`--max-players`, `--max-spectators`), and the newcomer's address group would
    /// push out neither ([`fair_push_out`]): refused before the handshake, whichever it would have
    /// been.
    AllFull(usize, usize),
    /// `--max-per-address`, reached by the client's address group.
    FromThisAddress(usize),
    /// [`Limits::max_spectators_per_address`], reached by the client's address group.
    SpectatorsFromThisAddress(usize),
    /// No handshake slots at all (`max_handshakes` is 0): nobody can log in.
    Busy,
    /// The address opened new connections faster than [`Limits::connect_rate`].
    TooFast,
}

impl Refusal {
    /// For the log.
    #[must_use]
    pub fn reason(self) -> &'static str {
        match self {
            Refusal::Full(_) | Refusal::AllFull(..) => "server full",
            Refusal::Spectators(_) => "spectators full",
            Refusal::FromThisAddress(_) => "too many connections from this address",
            Refusal::SpectatorsFromThisAddress(_) => "too many spectators from this address",
            Refusal::Busy => "too many connections logging in",
            Refusal::TooFast => "connecting too fast",
        }
    }

    /// For the client (its `ssh` prints it).
    #[must_use]
    pub fn message(self) -> String {
        match self {
            Refusal::Full(1) => "mazewalk: the server is full (one player at a time); try again later".into(),
            Refusal::Full(n) => format!("mazewalk: the server is full ({n} players); try again later"),
            Refusal::AllFull(players, spectators) => format!(
                "mazewalk: the server is full ({players} players, {spectators} watching); try again later"
            ),
            Refusal::Spectators(0) => "mazewalk: this server takes no spectators".into(),
            Refusal::Spectators(n) => {
                format!("mazewalk: every spectator's place is taken ({n} watching); try again later")
            }
            Refusal::FromThisAddress(n) => {
                let n = if n == 1 { "a connection".to_owned() } else { format!("{n} connections") };
                format!("mazewalk: {n} from your address already; close one, or try again later")
            }
            Refusal::SpectatorsFromThisAddress(n) => {
                let n = if n == 1 { "a spectator".to_owned() } else { format!("{n} spectators") };
                format!("mazewalk: {n} from your address already; close one, or try again later")
            }
            Refusal::Busy => {
                "mazewalk: too many players are logging in right now; try again in a few seconds".into()
            }
            Refusal::TooFast => {
                "mazewalk: too many new connections from your address; try again in a few seconds".into()
            }
        }
    }
}

/// A new connection's slot: its id, and the handshake it pushed out, if any (to be closed).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Admitted {
    /// The new connection's id.
    pub id: ConnId,
    /// The handshake that made room for it.
    pub evicted: Option<ConnId>,
}

/// A connection still in the handshake.
#[derive(Clone, Copy, Debug)]
struct Handshake {
    /// Its address.
    ip: IpAddr,
    group: IpAddr,
    /// When it last moved on (connected, exchanged keys, asked to log in), seconds.
    progress: f64,
}

/// What a connection that logged in does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Role {
    /// Walks the maze.
    Player,
    /// Watches the players (`ssh watch@…`).
    Spectator,
}

/// A connection that logged in.
#[derive(Clone, Copy, Debug)]
struct Place {
    /// Its address group ([`address_group`]).
    group: IpAddr,
    /// The prefixes it is counted in when a full server shares its places ([`address_prefixes`]).
    prefixes: [IpAddr; 3],
    /// When it logged in or last pressed a key ([`Slots::active`]), seconds.
    active: f64,
}

/// Connections of one address group.
#[derive(Clone, Copy, Debug, Default)]
struct Counts {
    handshakes: usize,
    /// Players and spectators.
    players: usize,
    /// Spectators (of `players`).
    spectators: usize,
}

/// Every open connection's slot (see the module's doc).
#[derive(Debug)]
pub(crate) struct Slots {
    limits: Limits,
    next_id: ConnId,
    /// Handshakes by id (oldest first).
    handshakes: BTreeMap<ConnId, Handshake>,
    /// Players by id.
    players: HashMap<ConnId, Place>,
    /// Spectators by id.
    spectators: HashMap<ConnId, Place>,
    /// The places of each role (players, spectators) by prefix level and prefix ([`fair_push_out`]'s
    /// counts), kept as places come and go: a full server's newcomer is weighed in one pass.
    prefix_counts: [PrefixCounts; 2],
    groups: HashMap<IpAddr, Counts>,
    /// New connections' budgets, by group (forgotten once full again).
    rates: HashMap<IpAddr, RateLimit>,
}

impl Slots {
    /// No connections, under `limits`.
    #[must_use]
    pub fn new(limits: &Limits) -> Slots {
        Slots {
            limits: *limits,
            next_id: 0,
            handshakes: BTreeMap::new(),
            players: HashMap::new(),
            spectators: HashMap::new(),
            prefix_counts: [PrefixCounts::default(), PrefixCounts::default()],
            groups: HashMap::new(),
            rates: HashMap::new(),
        }
    }

    /// A handshake slot for a new connection from `ip` at `now`, or why not.
    ///
    /// # Errors
    /// The [`Refusal`]: players full, the address group's connections or rate, no handshake slot.
    pub(crate) fn admit(&mut self, ip: IpAddr, now: f64) -> Result<Admitted, Refusal> {
        let group = address_group(ip);
        let limits = &self.limits;
        if self.rates.len() > 4 * (self.handshakes.len() + self.players.len()) + 1024 {
            self.rates.retain(|_, bucket| !bucket.is_full(now)); // bounded by what is recent
        }
        let burst = u32::try_from(2 * limits.max_per_address).unwrap_or(u32::MAX);
        let rate =
            self.rates.entry(group).or_insert_with(|| RateLimit::per_second(limits.connect_rate, burst, now));
        if rate.take(1, now) == 0 {
            return Err(Refusal::TooFast);
        }
        if self.players.len() >= limits.max_players
            && self.spectators.len() >= limits.max_spectators
            && self.push_out(Role::Player, ip).is_none()
            && self.push_out(Role::Spectator, ip).is_none()
        {
            return Err(if limits.max_spectators == 0 {
                Refusal::Full(limits.max_players)
            } else {
                Refusal::AllFull(limits.max_players, limits.max_spectators) // whichever it is, no room
            });
        }
        let counts = self.groups.get(&group).copied().unwrap_or_default();
        if counts.handshakes + counts.players >= limits.max_per_address {
            return Err(Refusal::FromThisAddress(limits.max_per_address));
        }
        let evicted = if self.handshakes.len() >= limits.max_handshakes {
            Some(self.victim().ok_or(Refusal::Busy)?)
        } else {
            None
        };
        if let Some(victim) = evicted {
            self.release(victim);
        }
        let id = self.next_id;
        self.next_id += 1;
        self.handshakes.insert(id, Handshake { ip, group, progress: now });
        self.groups.entry(group).or_default().handshakes += 1;
        Ok(Admitted { id, evicted })
    }

    /// The handshake to push out for a newcomer: the one longest without progress (the oldest of
    /// those, on a tie). A scan of at most `max_handshakes`, once per newcomer when all are taken.
    fn victim(&self) -> Option<ConnId> {
        self.handshakes.iter().min_by(|a, b| a.1.progress.total_cmp(&b.1.progress)).map(|(id, _)| *id)
    }

    /// The handshake `id` moved on at `now` (exchanged keys, asked to log in): it is pushed out
    /// after those that have not since.
    pub(crate) fn progress(&mut self, id: ConnId, now: f64) {
        if let Some(handshake) = self.handshakes.get_mut(&id) {
            handshake.progress = handshake.progress.max(now);
        }
    }

    /// The handshake `id` logged in at `now`: it becomes a player or a spectator, as `role` says.
    /// Where every place of its role is taken, it takes one of the address holding the most
    /// ([`fair_push_out`]): the id of the connection pushed out (its slot is free already; it is to
    /// be told and closed).
    ///
    /// # Errors
    /// [`Refusal::Full`] when every player's slot is taken and nobody gives way,
    /// [`Refusal::Spectators`] every spectator's, [`Refusal::SpectatorsFromThisAddress`] the
    /// spectators' of its address group (it stays a handshake).
    pub(crate) fn promote(&mut self, id: ConnId, role: Role, now: f64) -> Result<Option<ConnId>, Refusal> {
        let Some(Handshake { ip, group, .. }) = self.handshakes.get(&id).copied() else {
            return Ok(None); // logged in already, or gone
        };
        let per_address = self.limits.max_spectators_per_address;
        let counts = self.groups.get(&group).copied().unwrap_or_default();
        if role == Role::Spectator && counts.spectators >= per_address {
            return Err(Refusal::SpectatorsFromThisAddress(per_address));
        }
        let (taken, max, full) = match role {
            Role::Player => {
                (self.players.len(), self.limits.max_players, Refusal::Full as fn(usize) -> Refusal)
            }
            Role::Spectator => (self.spectators.len(), self.limits.max_spectators, Refusal::Spectators as _),
        };
        let pushed_out = if taken >= max {
            let victim = self.push_out(role, ip).ok_or(full(max))?;
            self.release(victim);
            Some(victim)
        } else {
            None
        };
        let counts = self.groups.entry(group).or_default();
        counts.handshakes -= 1;
        counts.players += 1;
        counts.spectators += usize::from(role == Role::Spectator);
        let place = Place { group, prefixes: address_prefixes(ip), active: now };
        self.prefix_counts[role as usize].add(&place.prefixes);
        match role {
            Role::Player => self.players.insert(id, place),
            Role::Spectator => self.spectators.insert(id, place),
        };
        self.handshakes.remove(&id);
        Ok(pushed_out)
    }

    /// Which of the `role`'s places a newcomer from `ip` would push out ([`fair_push_out`]; of an
    /// address's places, the one that pressed no key for the longest). One pass over the places,
    /// each weighed by the counts kept as places come and go ([`Slots::prefix_counts`]): no
    /// allocation under the lock, whatever the number of places.
    fn push_out(&self, role: Role, ip: IpAddr) -> Option<ConnId> {
        let taken = match role {
            Role::Player => &self.players,
            Role::Spectator => &self.spectators,
        };
        let counts = &self.prefix_counts[role as usize];
        // The heaviest holder's idlest place; among equals the newest, as `fair_push_out` over the
        // places in the order they came (its `max_by` keeps the last of equals).
        let (victim, theirs) = taken
            .iter()
            .map(|(&id, place)| (counts.weight(&place.prefixes), place.active, id, place.prefixes))
            .max_by(|a, b| a.0.cmp(&b.0).then(b.1.total_cmp(&a.1)).then(a.2.cmp(&b.2)))
            .map(|(_, _, id, prefixes)| (id, prefixes))?;
        let mine = address_prefixes(ip);
        let level = (0..3).find(|&level| theirs[level] != mine[level])?;
        (counts.count(level, theirs[level]) >= counts.count(level, mine[level]) + 2).then_some(victim)
    }

    /// The player or spectator `id` pressed a key at `now`: it is pushed out after those that have
    /// not since.
    pub(crate) fn active(&mut self, id: ConnId, now: f64) {
        if let Some(place) = self.players.get_mut(&id).or(self.spectators.get_mut(&id)) {
            place.active = place.active.max(now);
        }
    }

    /// The connection `id` closed (or was pushed out): its slot is free.
    pub fn release(&mut self, id: ConnId) {
        let (group, was_player, was_spectator) = match self.handshakes.remove(&id) {
            Some(handshake) => (handshake.group, false, false),
            None => match (self.players.remove(&id), self.spectators.remove(&id)) {
                (Some(place), _) => {
                    self.prefix_counts[Role::Player as usize].remove(&place.prefixes);
                    (place.group, true, false)
                }
                (None, Some(place)) => {
                    self.prefix_counts[Role::Spectator as usize].remove(&place.prefixes);
                    (place.group, true, true)
                }
                (None, None) => return,
            },
        };
        if let Some(counts) = self.groups.get_mut(&group) {
            if was_player {
                counts.players -= 1;
                counts.spectators -= usize::from(was_spectator);
            } else {
                counts.handshakes -= 1;
            }
            if counts.players + counts.handshakes == 0 {
                self.groups.remove(&group);
            }
        }
    }

    /// Players now.
    #[must_use]
    pub fn players(&self) -> usize {
        self.players.len()
    }

    /// Spectators now.
    #[must_use]
    pub fn spectators(&self) -> usize {
        self.spectators.len()
    }

    /// The connections of `ip`'s address group that logged in (players and spectators): the
    /// screens that share its drawing budget ([`Limits::render_rate`]), at least 1.
    #[must_use]
    pub fn screens_from(&self, ip: IpAddr) -> usize {
        self.groups.get(&address_group(ip)).map_or(0, |counts| counts.players).max(1)
    }

    /// Handshakes now.
    #[must_use]
    pub fn handshakes(&self) -> usize {
        self.handshakes.len()
    }

    /// Whether `id` holds a slot (as a handshake or a player).
    #[must_use]
    #[cfg(test)]
    pub fn holds(&self, id: ConnId) -> bool {
        self.handshakes.contains_key(&id)
            || self.players.contains_key(&id)
            || self.spectators.contains_key(&id)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ip(s: &str) -> IpAddr {
        s.parse().unwrap()
    }

    fn limits(max_players: usize, max_handshakes: usize, max_per_address: usize) -> Limits {
        // (no spectators: a newcomer finding the players full is refused at once)
        let max_spectators = 0;
        Limits {
            max_players,
            max_spectators,
            max_handshakes,
            max_per_address,
            connect_rate: 1000.0,
            ..Limits::default()
        }
    }

    /// Issue #34: one /64 is one address; an IPv4-mapped address is its IPv4 address.
    #[test]
    fn ipv6_addresses_are_grouped_by_their_64() {
        assert_eq!(address_group(ip("2001:db8:1:2:aaaa:bbbb:cccc:dddd")), ip("2001:db8:1:2::"));
        assert_eq!(address_group(ip("2001:db8:1:2::1")), address_group(ip("2001:db8:1:2:ffff::9")));
        assert_ne!(address_group(ip("2001:db8:1:2::1")), address_group(ip("2001:db8:1:3::1")));
        assert_eq!(address_group(ip("::ffff:192.0.2.7")), ip("192.0.2.7"));
        assert_eq!(address_group(ip("192.0.2.7")), ip("192.0.2.7"));
        let mut slots = Slots::new(&limits(100, 100, 2));
        slots.admit(ip("2001:db8::1"), 0.0).unwrap();
        slots.admit(ip("2001:db8::2:3"), 0.0).unwrap();
        assert_eq!(
            slots.admit(ip("2001:db8::ffff:1"), 0.0),
            Err(Refusal::FromThisAddress(2)),
            "the same /64"
        );
        assert!(slots.admit(ip("2001:db8:0:1::1"), 0.0).is_ok(), "the next /64");
    }

    /// Red-team pass 3: the screens sharing a drawing budget are the group's logged-in connections
    /// (players and spectators, not handshakes), at least 1; another group's are its own.
    #[test]
    fn the_screens_of_a_group_are_its_logged_in_connections() {
        let mut slots = Slots::new(&Limits { max_spectators: 4, ..limits(100, 100, 16) });
        assert_eq!(slots.screens_from(ip("10.0.0.1")), 1, "none yet: a lone screen's whole budget");
        let ids: Vec<ConnId> = (0..4).map(|_| slots.admit(ip("2001:db8::1"), 0.0).unwrap().id).collect();
        assert_eq!(slots.screens_from(ip("2001:db8::9")), 1, "handshakes draw nothing");
        slots.promote(ids[0], Role::Player, 0.0).unwrap();
        slots.promote(ids[1], Role::Player, 0.0).unwrap();
        slots.promote(ids[2], Role::Spectator, 0.0).unwrap();
        assert_eq!(slots.screens_from(ip("2001:db8::2")), 3, "the same /64");
        assert_eq!(slots.screens_from(ip("2001:db8:0:1::1")), 1, "another /64");
        slots.release(ids[0]);
        assert_eq!(slots.screens_from(ip("2001:db8::1")), 2);
    }

    /// Issue #34: connections in the handshake filled --max-players and locked players out. Now
    /// they have their own slots: players still get in, and players never lose theirs to them.
    #[test]
    fn handshakes_never_take_a_players_slot() {
        let mut slots = Slots::new(&limits(2, 4, 100));
        let a = slots.admit(ip("10.0.0.1"), 0.0).unwrap().id;
        slots.promote(a, Role::Player, 0.0).unwrap();
        for i in 0..3 {
            slots.admit(ip(&format!("10.0.1.{i}")), 0.0).unwrap();
        }
        assert_eq!((slots.players(), slots.handshakes()), (1, 3));
        let b = slots.admit(ip("10.0.2.1"), 0.0).unwrap().id;
        slots.promote(b, Role::Player, 0.0).unwrap();
        assert_eq!(slots.players(), 2);
        assert_eq!(slots.admit(ip("10.0.3.1"), 0.0), Err(Refusal::Full(2)), "players full: refused at once");
        slots.release(a);
        assert!(slots.admit(ip("10.0.3.1"), 0.0).is_ok());
    }

    /// Issue #40: a newcomer takes the slot of the handshake longest without progress, whoever holds
    /// it; one that moved on (exchanged keys, asked to log in) is pushed out after the idle ones.
    #[test]
    fn a_newcomer_pushes_out_the_handshake_longest_without_progress() {
        let mut slots = Slots::new(&limits(100, 4, 100));
        let held: Vec<ConnId> =
            (0..4).map(|i| slots.admit(ip(&format!("192.0.2.{i}")), f64::from(i)).unwrap().id).collect();
        slots.progress(held[0], 3.5); // the oldest exchanged its keys: it is the newest in progress
        let first = slots.admit(ip("198.51.100.1"), 4.0).unwrap();
        assert_eq!(first.evicted, Some(held[1]), "the oldest idle one, not the oldest");
        let second = slots.admit(ip("192.0.2.1"), 5.0).unwrap();
        assert_eq!(second.evicted, Some(held[2]), "any address may push out any other's");
        assert!(slots.holds(held[0]) && slots.holds(first.id) && slots.holds(second.id));
        assert_eq!(slots.handshakes(), 4, "never more than the slots");
        slots.progress(ConnId::MAX, 6.0); // a connection that is gone: nothing happens
        assert_eq!(Slots::new(&limits(100, 0, 100)).admit(ip("192.0.2.9"), 0.0), Err(Refusal::Busy));
    }

    /// Issue #40's attack: 1,000 addresses open 500 idle handshakes a second into 32 slots (each
    /// address once every 2 s: no per-address limit stops them). A newcomer that moves on every 20 ms
    /// (a key exchange on loopback takes a few) logs in; one that says nothing is pushed out after
    /// 32 arrivals, 64 ms.
    #[test]
    fn idle_handshakes_from_a_thousand_addresses_cannot_keep_a_player_out() {
        let mut slots = Slots::new(&limits(100, 32, 16));
        let mut now = 0.0;
        let mut attacker = 0u32;
        let mut attack = |slots: &mut Slots, now: f64| {
            let from = IpAddr::from([10, 0, (attacker / 250) as u8, (attacker % 250) as u8]);
            attacker = (attacker + 1) % 1000;
            slots.admit(from, now).expect("an attacker is never refused either");
        };
        for _ in 0..2000 {
            now += 0.002;
            attack(&mut slots, now);
        }
        assert_eq!(slots.handshakes(), 32);
        let player = slots.admit(ip("198.51.100.7"), now).expect("a newcomer gets a slot").id;
        let idle = slots.admit(ip("198.51.100.8"), now).expect("a newcomer gets a slot").id;
        for step in 1..=40 {
            now += 0.002;
            attack(&mut slots, now);
            if step % 10 == 0 {
                slots.progress(player, now); // keys exchanged, then the login asked for…
            }
            if step == 20 {
                assert!(slots.holds(idle), "the older idle ones go first");
            }
            if step == 32 {
                assert!(!slots.holds(idle), "the idle newcomer is gone within 32 arrivals");
            }
        }
        assert!(slots.holds(player));
        slots.promote(player, Role::Player, 0.0).expect("logged in");
        assert_eq!((slots.players(), slots.handshakes()), (1, 31), "its handshake slot is free again");
    }

    /// Issue #43: spectators have their own slots. A full game still lets spectators in (and tells
    /// the player who finds it full when it logs in); full spectators leave players their slots;
    /// both full, a newcomer is refused at once; spectators count against their address.
    #[test]
    fn spectators_never_take_a_players_slot_nor_players_theirs() {
        let mut slots = Slots::new(&Limits { max_spectators: 1, ..limits(1, 8, 3) });
        let alice = slots.admit(ip("10.0.0.1"), 0.0).unwrap().id;
        slots.promote(alice, Role::Player, 0.0).unwrap();
        let watcher = slots.admit(ip("10.0.0.2"), 0.0).expect("the game is full, the spectators are not").id;
        let bob = slots.admit(ip("10.0.0.3"), 0.0).unwrap().id;
        assert_eq!(slots.promote(bob, Role::Player, 0.0), Err(Refusal::Full(1)), "told when it logs in");
        slots.promote(watcher, Role::Spectator, 0.0).unwrap();
        assert_eq!((slots.players(), slots.spectators()), (1, 1));
        assert_eq!(slots.promote(bob, Role::Spectator, 0.0), Err(Refusal::Spectators(1)));
        slots.release(bob);
        assert_eq!(
            slots.admit(ip("10.0.0.4"), 0.0),
            Err(Refusal::AllFull(1, 1)),
            "both full: refused at once"
        );
        slots.release(alice);
        let carol = slots.admit(ip("10.0.0.4"), 0.0).unwrap().id;
        slots.promote(carol, Role::Player, 0.0).expect("the player's slot, not taken by the spectator");
        slots.release(watcher);
        slots.release(carol);
        assert_eq!((slots.players(), slots.spectators()), (0, 0));
        let group: Vec<ConnId> = (0..3).map(|_| slots.admit(ip("10.0.0.9"), 0.0).unwrap().id).collect();
        slots.promote(group[0], Role::Spectator, 0.0).unwrap();
        assert_eq!(slots.admit(ip("10.0.0.9"), 0.0), Err(Refusal::FromThisAddress(3)), "a spectator counts");
        assert!(Refusal::Spectators(1).message().contains("try again later"));
    }

    /// Red-team pass: one address logged in 16 spectators (its `--max-per-address`) and held every
    /// spectator's place for good. Now an address group holds at most its share; its players, and
    /// the other addresses' spectators, are let in; a spectator leaving gives its place back.
    #[test]
    fn one_address_holds_no_more_than_its_share_of_the_spectators() {
        let mut slots =
            Slots::new(&Limits { max_spectators: 16, max_spectators_per_address: 4, ..limits(16, 64, 16) });
        let admit = |slots: &mut Slots, from: &str, role| {
            let id = slots.admit(ip(from), 0.0).unwrap().id;
            (id, slots.promote(id, role, 0.0))
        };
        let watchers: Vec<ConnId> =
            (0..4).map(|_| admit(&mut slots, "10.0.0.1", Role::Spectator).0).collect();
        let (fifth, refused) = admit(&mut slots, "10.0.0.1", Role::Spectator);
        assert_eq!(refused, Err(Refusal::SpectatorsFromThisAddress(4)));
        assert!(refused.unwrap_err().message().contains("4 spectators from your address"));
        slots.release(fifth);
        assert_eq!(admit(&mut slots, "10.0.0.1", Role::Player).1, Ok(None), "a player from there");
        assert_eq!(admit(&mut slots, "10.0.0.2", Role::Spectator).1, Ok(None), "a spectator from elsewhere");
        slots.release(watchers[0]);
        assert_eq!(admit(&mut slots, "10.0.0.1", Role::Spectator).1, Ok(None), "a place given back");
        assert_eq!(slots.spectators(), 5);
    }

    /// Logs a newcomer from `from` in as `role` at `now`: its id, and whom it pushed out (or why not).
    fn log_in(
        slots: &mut Slots,
        from: &str,
        role: Role,
        now: f64,
    ) -> (ConnId, Result<Option<ConnId>, Refusal>) {
        let id = slots.admit(ip(from), now).expect("a handshake slot").id;
        (id, slots.promote(id, role, now))
    }

    /// As [`log_in`], refused before the handshake or when it logs in: whom it pushed out.
    fn try_in(slots: &mut Slots, from: &str, role: Role, now: f64) -> Result<Option<ConnId>, Refusal> {
        let id = slots.admit(ip(from), now)?.id;
        slots.promote(id, role, now)
    }

    /// Red-team pass 4, F1: 2 addresses × 16 held every player's place of 32, and 4 × 4 every
    /// spectator's, pressing a key now and then; newcomers were refused for good. Now a newcomer from
    /// elsewhere pushes out the heaviest address's player that pressed no key for the longest (and
    /// a spectator likewise), the heavy addresses give way one place at a time until no address
    /// holds two more than a newcomer's, and a heavy address never gets in at its own expense.
    #[test]
    fn a_full_server_gives_a_newcomer_the_heaviest_addresss_idlest_place() {
        let mut slots =
            Slots::new(&Limits { max_spectators: 16, max_spectators_per_address: 4, ..limits(32, 64, 16) });
        let mut held: HashMap<ConnId, &str> = HashMap::new();
        for (k, from) in ["10.0.0.2", "10.0.3.3"].into_iter().enumerate() {
            for n in 0..16 {
                let (id, promoted) = log_in(&mut slots, from, Role::Player, f64::from(n));
                assert_eq!(promoted, Ok(None), "{from} #{n}: room still");
                slots.active(id, 100.0 + f64::from(n) + if k == 1 { 0.5 } else { 0.0 });
                held.insert(id, from);
            }
        }
        for from in ["10.0.1.1", "10.0.1.2", "10.0.1.3", "10.0.1.4"] {
            for _ in 0..4 {
                assert_eq!(log_in(&mut slots, from, Role::Spectator, 0.0).1, Ok(None));
            }
        }
        assert_eq!((slots.players(), slots.spectators()), (32, 16));
        // the heavy addresses' own newcomers: refused
        assert_eq!(slots.admit(ip("10.0.0.2"), 200.0), Err(Refusal::FromThisAddress(16)));
        assert_eq!(slots.admit(ip("10.0.1.1"), 200.0).map(|_| ()), Ok(()), "room for its handshake…");
        // a newcomer from elsewhere gets in, in the place of the idlest of the heaviest (a tie of
        // 16 and 16: the one whose last key is the oldest, 10.0.0.2's first, at 100 s)
        let (newcomer, promoted) = log_in(&mut slots, "192.0.2.1", Role::Player, 200.0);
        let first = promoted.expect("let in").expect("somebody pushed out");
        assert_eq!((held[&first], slots.holds(first)), ("10.0.0.2", false));
        assert!(slots.holds(newcomer));
        assert_eq!(slots.players(), 32, "never more than the places");
        // 10.0.0.2 holds 15 now: 10.0.3.3's idlest goes next, and so on, the two taking turns
        let (_, promoted) = log_in(&mut slots, "192.0.2.2", Role::Player, 201.0);
        assert_eq!(held[&promoted.unwrap().unwrap()], "10.0.3.3");
        // a key keeps a player in: 10.0.3.3's players and 10.0.0.2's next idlest press one (15 and
        // 15: the idlest of both addresses goes), the one after it goes
        let holding = |slots: &Slots, from: &str| {
            let mut ids: Vec<ConnId> =
                held.iter().filter(|(id, f)| **f == from && slots.holds(**id)).map(|(id, _)| *id).collect();
            ids.sort_unstable();
            ids
        };
        for id in holding(&slots, "10.0.3.3") {
            slots.active(id, 202.0);
        }
        let next = holding(&slots, "10.0.0.2");
        slots.active(next[0], 202.0);
        let (_, promoted) = log_in(&mut slots, "192.0.2.3", Role::Player, 203.0);
        assert_eq!(promoted, Ok(Some(next[1])), "the idlest, not the oldest");
        // newcomers from fresh addresses until the heavy ones hold no more than one more each
        let mut fresh = 10;
        let refusal = loop {
            match try_in(&mut slots, &format!("198.51.{fresh}.1"), Role::Player, 210.0) {
                Ok(pushed) => assert!(pushed.is_some(), "the server stays full"),
                Err(refusal) => break refusal,
            }
            fresh += 1;
            assert!(fresh < 100, "it ends");
        };
        // (let in to log in, as it might have come to watch: it would have pushed out a spectator)
        assert_eq!(refusal, Refusal::Full(32), "nobody to push out: refused");
        let left = |from: &str| held.iter().filter(|(id, f)| **f == from && slots.holds(**id)).count();
        assert_eq!((left("10.0.0.2"), left("10.0.3.3")), (1, 1), "an even share: one each");
        assert_eq!(slots.players(), 32);
        // spectators alike: 4 addresses × 4 give way to a watcher from elsewhere
        let (watcher, promoted) = log_in(&mut slots, "203.0.113.9", Role::Spectator, 220.0);
        assert!(matches!(promoted, Ok(Some(_))) && slots.holds(watcher));
        assert_eq!(slots.spectators(), 16);
        assert_eq!(
            try_in(&mut slots, "10.0.1.2", Role::Spectator, 221.0),
            Err(Refusal::AllFull(32, 16)),
            "a heavy address's own: refused before its handshake"
        );
    }

    /// Red-team pass 4, F1 on IPv6: one customer's /56 (or /48) is 256 (65,536) /64s, each an address
    /// group of its own for the caps. A full server counts the /48, then the /56, then the /64:
    /// players from 32 /64s of one /56 give way to another customer's, and to another /56 of the
    /// same /48, but not to a /64 of their own /56 holding one less.
    #[test]
    fn one_customers_many_64s_count_as_one_holder_when_the_server_is_full() {
        assert_eq!(
            address_prefixes(ip("2001:db8:1:2ff:1:2:3:4")),
            [ip("2001:db8:1::"), ip("2001:db8:1:200::"), ip("2001:db8:1:2ff::")]
        );
        assert_eq!(
            address_prefixes(ip("::ffff:192.0.2.7")),
            [ip("192.0.2.0"), ip("192.0.2.0"), ip("192.0.2.7")]
        );
        let mut slots = Slots::new(&limits(32, 64, 16));
        for n in 0..32 {
            let from = format!("2001:db8:1:2{n:02x}::1");
            assert_eq!(log_in(&mut slots, &from, Role::Player, 0.0).1, Ok(None));
        }
        // (no spectators here: a newcomer who would push nobody out is refused before its handshake)
        let refused = |slots: &mut Slots, from: &str| try_in(slots, from, Role::Player, 1.0);
        assert_eq!(refused(&mut slots, "2001:db8:1:2ff::1"), Err(Refusal::Full(32)), "its own /56");
        assert!(matches!(refused(&mut slots, "2001:db8:1:300::1"), Ok(Some(_))), "another /56 of the /48");
        assert!(matches!(refused(&mut slots, "2001:db8:2::1"), Ok(Some(_))), "another /48");
        assert!(matches!(refused(&mut slots, "192.0.2.1"), Ok(Some(_))), "an IPv4 address");
        // the pure rule: an IPv4 address holding 2 outweighs a /48 holding 2 over two /64s
        let held = [
            (ip("2001:db8::1"), 0.0),
            (ip("192.0.2.1"), 1.0),
            (ip("2001:db8:0:1::1"), 2.0),
            (ip("192.0.2.1"), 3.0),
        ];
        assert_eq!(fair_push_out(&held, ip("198.51.100.1")), Some(1));
        assert_eq!(fair_push_out(&held, ip("192.0.2.1")), None, "never its own");
        assert_eq!(fair_push_out(&held[..2], ip("198.51.100.1")), None, "one each: nobody gives way");
        assert_eq!(fair_push_out(&[], ip("198.51.100.1")), None);
    }

    /// Red-team pass 4, left then: IPv4 addresses counted apart, so 32 addresses of one /24 (one
    /// host's rented block) held every place against anyone. Now a full server counts an IPv4
    /// address's /24 first: they give way to a newcomer from another /24, not to their own.
    #[test]
    fn many_addresses_of_one_24_count_as_one_holder_when_the_server_is_full() {
        let mut slots = Slots::new(&limits(32, 64, 16));
        for n in 0..32 {
            assert_eq!(log_in(&mut slots, &format!("198.51.100.{n}"), Role::Player, 0.0).1, Ok(None));
        }
        let refused = |slots: &mut Slots, from: &str| try_in(slots, from, Role::Player, 1.0);
        assert_eq!(refused(&mut slots, "198.51.100.77"), Err(Refusal::Full(32)), "its own /24");
        assert!(matches!(refused(&mut slots, "198.51.101.1"), Ok(Some(_))), "the next /24");
        assert!(matches!(refused(&mut slots, "2001:db8::1"), Ok(Some(_))), "an IPv6 address");
        // the pure rule: within a /24 addresses count apart, as before
        let held = [(ip("192.0.2.1"), 0.0), (ip("192.0.2.1"), 1.0), (ip("192.0.2.2"), 2.0)];
        assert_eq!(fair_push_out(&held, ip("192.0.2.3")), Some(0), "its heaviest address gives way");
        assert_eq!(fair_push_out(&held, ip("192.0.2.2")), None, "one less than it: no");
        assert_eq!(fair_push_out(&held, ip("203.0.113.1")), Some(0), "3 against 0");
        assert_eq!(fair_push_out(&held[..1], ip("203.0.113.1")), None, "1 against 0: an even share");
    }

    #[test]
    fn an_address_connecting_too_fast_is_slowed_and_every_slot_comes_back() {
        let mut slots = Slots::new(&Limits { connect_rate: 2.0, ..limits(100, 100, 3) });
        let mut ids = Vec::new();
        for i in 0..6 {
            let id = slots.admit(ip("192.0.2.9"), 0.0).unwrap().id;
            assert!(i < 3 || slots.handshakes() <= 3);
            slots.release(id);
            ids.push(id);
        }
        assert_eq!(slots.admit(ip("192.0.2.9"), 0.0), Err(Refusal::TooFast), "a burst of 2 × 3");
        assert!(slots.admit(ip("192.0.2.9"), 0.5).is_ok(), "one more after 1 / rate");
        assert!(slots.admit(ip("192.0.2.10"), 0.5).is_ok(), "another address is not slowed");
        let left: Vec<ConnId> = (0..100).filter(|&id| slots.holds(id)).collect();
        for id in left {
            slots.release(id);
        }
        assert_eq!((slots.players(), slots.handshakes()), (0, 0));
        assert!(slots.groups.is_empty(), "nothing kept for closed connections");
    }

    /// A group's connections are counted while any of them is open: one leaving frees its own slot
    /// only, whether it was a handshake, a player or a spectator.
    #[test]
    fn a_connection_leaving_frees_its_own_slot_only() {
        let mut slots =
            Slots::new(&Limits { max_spectators: 8, max_spectators_per_address: 1, ..limits(8, 8, 2) });
        let from = "192.0.2.1";
        let first = slots.admit(ip(from), 0.0).unwrap().id;
        let second = slots.admit(ip(from), 0.0).unwrap().id;
        slots.release(first);
        let third = slots.admit(ip(from), 1.0).expect("the slot given back").id;
        assert_eq!(slots.admit(ip(from), 2.0), Err(Refusal::FromThisAddress(2)), "the other two still count");
        slots.promote(second, Role::Spectator, 3.0).unwrap();
        slots.promote(third, Role::Player, 3.0).unwrap();
        slots.release(third);
        assert_eq!(
            try_in(&mut slots, from, Role::Spectator, 4.0),
            Err(Refusal::SpectatorsFromThisAddress(1)),
            "the spectator still counts"
        );
        assert_eq!(
            slots.admit(ip(from), 5.0),
            Err(Refusal::FromThisAddress(2)),
            "and the refused one's handshake"
        );
        slots.release(second);
        assert_eq!(slots.screens_from(ip(from)), 1);
        let (_, promoted) = log_in(&mut slots, "192.0.2.9", Role::Spectator, 6.0);
        assert_eq!(promoted, Ok(None), "another address's spectator");
        assert_eq!(slots.spectators(), 1);
    }

    /// Every refusal tells the log why in a few words, and the client what to do.
    #[test]
    fn every_refusal_says_why() {
        let reasons = [
            (Refusal::Full(4), "server full"),
            (Refusal::AllFull(4, 2), "server full"),
            (Refusal::Spectators(2), "spectators full"),
            (Refusal::FromThisAddress(2), "too many connections from this address"),
            (Refusal::SpectatorsFromThisAddress(2), "too many spectators from this address"),
            (Refusal::Busy, "too many connections logging in"),
            (Refusal::TooFast, "connecting too fast"),
        ];
        for (refusal, reason) in reasons {
            assert_eq!(refusal.reason(), reason);
            assert!(refusal.message().starts_with("mazewalk: "), "{refusal:?}");
        }
        let said = |refusal: Refusal| refusal.message();
        assert!(said(Refusal::Full(1)).contains("one player at a time"));
        assert!(said(Refusal::Full(4)).contains("(4 players)"));
        assert!(said(Refusal::AllFull(4, 2)).contains("(4 players, 2 watching)"));
        assert!(said(Refusal::Spectators(0)).contains("takes no spectators"));
        assert!(said(Refusal::Spectators(2)).contains("(2 watching)"));
        assert!(said(Refusal::FromThisAddress(1)).contains(": a connection from your address"));
        assert!(said(Refusal::FromThisAddress(3)).contains(": 3 connections from your address"));
        assert!(said(Refusal::SpectatorsFromThisAddress(1)).contains(": a spectator from your address"));
        assert!(said(Refusal::Busy).contains("logging in"));
        assert!(said(Refusal::TooFast).contains("too many new connections"));
    }

    /// The connection budgets of thousands of addresses that came once are forgotten once whole
    /// again (memory bounded by the connections open), never one that is still spent: an address
    /// connecting as fast as it can keeps to its burst and rate however many others come and go.
    #[test]
    fn the_connection_budgets_are_bounded_and_a_spent_one_is_kept() {
        let mut slots = Slots::new(&Limits { connect_rate: 8.0, ..limits(100, 100, 2) });
        let fast = ip("198.51.100.1");
        let mut let_in = 0;
        for n in 0..5000u32 {
            let now = f64::from(n) * 0.001;
            if let Ok(admitted) = slots.admit(fast, now) {
                slots.release(admitted.id);
                let_in += 1;
            }
            let id = slots.admit(IpAddr::from(Ipv4Addr::from(0x0a00_0000u32 + n)), now).unwrap().id;
            slots.release(id);
            assert!(slots.rates.len() <= 1024 + 2, "{} budgets at {n}", slots.rates.len());
        }
        assert!((43..=44).contains(&let_in), "{let_in}: a burst of 2 × 2, then 8 a second for 5 s");
        // many connections held open allow more budgets; once they close, the bound falls back
        let held: Vec<ConnId> = (0..300u32)
            .map(|n| slots.admit(IpAddr::from(Ipv4Addr::from(0x0b00_0000u32 + n)), 10.0).unwrap().id)
            .collect();
        for n in 0..1500u32 {
            let id = slots.admit(IpAddr::from(Ipv4Addr::from(0x0c00_0000u32 + n)), 10.0).unwrap().id;
            slots.release(id);
        }
        for id in held {
            slots.release(id);
        }
        let id = slots.admit(ip("203.0.113.1"), 20.0).unwrap().id;
        slots.release(id);
        assert!(slots.rates.len() <= 2, "{} budgets after all closed", slots.rates.len());
    }

    proptest::proptest! {
        #![proptest_config(proptest::test_runner::Config { cases: 32, ..Default::default() })]

        /// The places a full server's newcomer pushes out, weighed from the counts kept as places
        /// come and go, are those the rule [`fair_push_out`] picks from the places as they are: over
        /// random logins, key presses and leavings of addresses that share /24s, /48s and /56s.
        #[test]
        fn the_kept_counts_push_out_whom_the_rule_picks(
            ops in proptest::collection::vec((0u8..4, 0usize..12, 0usize..64, proptest::bool::ANY), 1..160)
        ) {
            const FROM: [&str; 12] = [
                "192.0.2.1", "192.0.2.2", "192.0.2.3", "198.51.100.1", "::ffff:192.0.2.1", "203.0.113.9",
                "2001:db8:1:1::1", "2001:db8:1:1::2", "2001:db8:1:2::1", "2001:db8:1:100::1",
                "2001:db8:2:1::1", "2001:db8:2:1::7",
            ];
            let mut slots = Slots::new(&Limits { max_spectators: 64, ..limits(64, 64, 64) });
            let mut from: HashMap<ConnId, IpAddr> = HashMap::new();
            for (step, &(op, who, which, spectator)) in ops.iter().enumerate() {
                let now = (step / 4) as f64; // (several steps at one time: ties to break)
                let role = if spectator { Role::Spectator } else { Role::Player };
                let ids: Vec<ConnId> = { let mut ids: Vec<ConnId> = from.keys().copied().collect(); ids.sort_unstable(); ids };
                match op {
                    0 | 1 => {
                        let Ok(admitted) = slots.admit(ip(FROM[who]), now) else { continue };
                        from.insert(admitted.id, ip(FROM[who]));
                        if op == 1 {
                            let _ = slots.promote(admitted.id, role, now);
                        }
                    }
                    2 if !ids.is_empty() => slots.active(ids[which % ids.len()], now),
                    3 if !ids.is_empty() => {
                        let id = ids[which % ids.len()];
                        slots.release(id);
                        from.remove(&id);
                    }
                    _ => {}
                }
                for role in [Role::Player, Role::Spectator] {
                    let taken = if role == Role::Player { &slots.players } else { &slots.spectators };
                    let mut places: Vec<(ConnId, f64)> = taken.iter().map(|(&id, p)| (id, p.active)).collect();
                    places.sort_unstable_by_key(|&(id, _)| id);
                    let held: Vec<(IpAddr, f64)> = places.iter().map(|&(id, active)| (from[&id], active)).collect();
                    for newcomer in FROM {
                        let want = fair_push_out(&held, ip(newcomer)).map(|k| places[k].0);
                        proptest::prop_assert_eq!(slots.push_out(role, ip(newcomer)), want);
                    }
                }
            }
            for id in from.into_keys() {
                slots.release(id);
            }
            proptest::prop_assert!(slots.prefix_counts.iter().all(|counts| counts.0.is_empty()), "nothing kept");
        }
    }
}
