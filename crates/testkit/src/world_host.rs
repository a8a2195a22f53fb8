//! A server's own world for the world task's tests, as small as the [`Host`] contract allows: its
//! players by id, the finishes not yet taken, and what it was told of the others. Labels follow
//! the in-process world's rule (the name's first character no one shows, else a spare one).
#![allow(missing_docs)] // moved from the tests that share it, whose items were not documented one by one

use std::collections::BTreeMap;
use std::sync::{Mutex, MutexGuard, PoisonError};

use glam::Vec2;
use mazewalk_serve::shared::codec::{Finish, PlayerRecord, Whereabouts, WinnerRecord};
use mazewalk_serve::shared::view::Others;
use mazewalk_serve::shared::{Host, LocalFinish, ServerId};

/// What the host holds.
#[derive(Default)]
pub struct State {
    pub players: BTreeMap<u32, PlayerRecord>,
    pub finished: Vec<LocalFinish>,
    /// The others as last told.
    pub others: Vec<(ServerId, PlayerRecord)>,
    pub online: bool,
    /// Every winner it was told of, in order.
    pub winners: Vec<WinnerRecord>,
    /// Finishes on other servers it was told of.
    pub heard_finishes: Vec<(ServerId, Finish)>,
    next_id: u32,
}

#[derive(Default)]
pub struct TestHost {
    state: Mutex<State>,
}

pub fn at(x: f32, y: f32) -> Whereabouts {
    Whereabouts { position: Vec2::new(x, y), heading_deg: 0.0, pitch_deg: 0.0, cell: 0 }
}

impl TestHost {
    pub fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// A player joins at `joined_ms`.
    pub fn join_at(&self, name: &str, where_: Whereabouts, joined_ms: u64) -> u32 {
        let mut s = self.lock();
        let id = s.next_id;
        s.next_id += 1;
        let label = s.free_label(name).unwrap_or('?');
        let color = (id % 8) as u8;
        s.players.insert(id, PlayerRecord { id, joined_ms, color, label, name: name.into(), at: where_ });
        id
    }

    pub fn join(&self, name: &str, where_: Whereabouts) -> u32 {
        self.join_at(name, where_, mazewalk_serve::shared::task::unix_ms())
    }

    pub fn moved(&self, id: u32, where_: Whereabouts) {
        if let Some(p) = self.lock().players.get_mut(&id) {
            p.at = where_;
        }
    }

    pub fn leave(&self, id: u32) {
        self.lock().players.remove(&id);
    }

    pub fn finish(&self, id: u32, seconds: f64) {
        let mut s = self.lock();
        let name = s.players[&id].name.clone();
        s.finished.push(LocalFinish { id, name, seconds });
    }

    /// The other server's player named `name`, as this host was told of it.
    pub fn other(&self, name: &str) -> Option<PlayerRecord> {
        self.lock().others.iter().find(|(_, p)| p.name == name).map(|(_, p)| p.clone())
    }

    pub fn label(&self, id: u32) -> char {
        self.lock().players[&id].label
    }

    pub fn position(&self, id: u32) -> Vec2 {
        self.lock().players[&id].at.position
    }
}

impl State {
    fn free_label(&self, name: &str) -> Option<char> {
        let taken = |c: char| {
            self.players.values().any(|p| p.label == c) || self.others.iter().any(|(_, p)| p.label == c)
        };
        let from_name = name.chars().filter(char::is_ascii_alphanumeric).map(|c| c.to_ascii_uppercase());
        from_name.chain('1'..='9').chain('A'..='Z').find(|&c| !taken(c))
    }
}

impl Host for TestHost {
    fn locals(&self, players: &mut Vec<PlayerRecord>, finished: &mut Vec<LocalFinish>) {
        let mut s = self.lock();
        players.clear();
        players.extend(s.players.values().cloned());
        finished.append(&mut s.finished);
    }

    fn others(&self, others: &Others, online: bool) {
        let mut s = self.lock();
        s.others = others.players().map(|(server, p)| (server, p.clone())).collect();
        s.online = online;
    }

    fn winner(&self, winner: &WinnerRecord) {
        self.lock().winners.push(winner.clone());
    }

    fn finished(&self, server: ServerId, finishes: &[Finish]) {
        self.lock().heard_finishes.extend(finishes.iter().map(|f| (server, f.clone())));
    }

    fn relabel(&self, ids: &[u32]) {
        let mut s = self.lock();
        for id in ids {
            let Some(name) = s.players.get(id).map(|p| p.name.clone()) else { continue };
            if let Some(label) = s.free_label(&name) {
                s.players.get_mut(id).expect("present").label = label;
            }
        }
    }
}
