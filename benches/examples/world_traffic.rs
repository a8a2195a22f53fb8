//! The shared world's cost on Redis, for BENCHMARKS.md ("The shared world on Redis"): a
//! `redis-server` of its own on loopback, server A with W walkers (each moves 30 times a second)
//! and server B with one player standing still, both world tasks in this process. For W = 1, 10,
//! 100: the commands and bytes a second A sends Redis (as Redis counts them), the bytes a second
//! Redis sends each subscribed server, and how long a move on A takes to reach B's world (p50 /
//! p99; the frame on B's player adds at most one look, 1/30 s, and its render).
//!
//! ```sh
//! cargo run --release -p mazewalk-bench --example world_traffic            # 10 s per W
//! cargo run --release -p mazewalk-bench --example world_traffic -- 3       # 3 s per W
//! ```

use mazewalk_testkit::redis_async as redis_server;
use mazewalk_testkit::world_host as host;

use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use glam::Vec2;
use host::{TestHost, at};
use mazewalk_serve::shared::codec::{Bounds, Finish, PlayerRecord, WinnerRecord};
use mazewalk_serve::shared::view::Others;
use mazewalk_serve::shared::{Host, LocalFinish, ServerId, SharedWorld, WorldConfig};
use redis_server::{Persistence, RedisServer};

const MAZE: &str = "be4c0123456789abcdef";

/// B's world, which notes when each position of A's first walker arrives.
#[derive(Default)]
struct Timed {
    host: TestHost,
    arrivals: Mutex<HashMap<(u32, u32), Instant>>,
}

impl Host for Timed {
    fn locals(&self, players: &mut Vec<PlayerRecord>, finished: &mut Vec<LocalFinish>) {
        self.host.locals(players, finished);
    }
    fn others(&self, others: &Others, online: bool) {
        let now = Instant::now();
        if let Some((_, p)) = others.players().find(|(_, p)| p.name == "w0") {
            let key = (p.at.position.x.to_bits(), p.at.position.y.to_bits());
            self.arrivals.lock().unwrap().entry(key).or_insert(now);
        }
        self.host.others(others, online);
    }
    fn winner(&self, winner: &WinnerRecord) {
        self.host.winner(winner);
    }
    fn finished(&self, server: ServerId, finishes: &[Finish]) {
        self.host.finished(server, finishes);
    }
    fn relabel(&self, ids: &[u32]) {
        self.host.relabel(ids);
    }
}

async fn info(con: &mut redis::aio::MultiplexedConnection, field: &str) -> u64 {
    let text: String = redis::cmd("INFO").arg("stats").query_async(con).await.unwrap();
    let line = text.lines().find(|l| l.starts_with(&format!("{field}:"))).unwrap();
    line.split(':').nth(1).unwrap().trim().parse().unwrap()
}

fn quantile(sorted: &[f64], q: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

#[tokio::main(flavor = "multi_thread", worker_threads = 2)]
async fn main() {
    let seconds: f64 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(10.0);
    let redis = RedisServer::start(Persistence::None).await;
    let bounds = Bounds { min: Vec2::ZERO, max: Vec2::splat(1000.0), cells: 1 };
    let config = WorldConfig::new(&redis.url(0), MAZE, bounds);
    println!(
        "walkers | A: commands/s | A → Redis KB/s | Redis → each server KB/s | move A → world B p50 / p99 ms | samples"
    );
    for walkers in [1usize, 10, 100] {
        let a = Arc::new(TestHost::default());
        let b = Arc::new(Timed::default());
        let ids: Vec<u32> = (0..walkers).map(|i| a.join(&format!("w{i}"), at(1.0, 1.0 + i as f32))).collect();
        b.host.join("still", at(500.0, 500.0));
        let world_a = SharedWorld::join(config.clone(), Arc::clone(&a) as Arc<dyn Host>).await.unwrap();
        let world_b = SharedWorld::join(config.clone(), Arc::clone(&b) as Arc<dyn Host>).await.unwrap();
        while b.host.lock().others.len() < walkers {
            tokio::time::sleep(Duration::from_millis(10)).await;
        }
        let mut con = redis.connection(0).await;
        let _: () = redis::cmd("CONFIG").arg("RESETSTAT").query_async(&mut con).await.unwrap();
        let (in0, out0, cmd0) = (
            info(&mut con, "total_net_input_bytes").await,
            info(&mut con, "total_net_output_bytes").await,
            info(&mut con, "total_commands_processed").await,
        );
        let stats0 = world_a.stats();
        let mut moved: Vec<((u32, u32), Instant)> = Vec::new();
        let step = Duration::from_secs_f64(1.0 / 30.0);
        let start = Instant::now();
        let mut due = start;
        let mut n = 0u32;
        while start.elapsed().as_secs_f64() < seconds {
            tokio::time::sleep_until(due.into()).await;
            due += step;
            n += 1;
            for (i, &id) in ids.iter().enumerate() {
                let position = Vec2::new(1.0 + (n % 900) as f32, 1.0 + i as f32);
                a.moved(id, at(position.x, position.y));
                if i == 0 {
                    moved.push(((position.x.to_bits(), position.y.to_bits()), Instant::now()));
                }
            }
        }
        let elapsed = start.elapsed().as_secs_f64();
        tokio::time::sleep(Duration::from_millis(300)).await; // the last moves arrive
        let stats = world_a.stats();
        let (in1, out1, cmd1) = (
            info(&mut con, "total_net_input_bytes").await,
            info(&mut con, "total_net_output_bytes").await,
            info(&mut con, "total_commands_processed").await,
        );
        let arrivals = b.arrivals.lock().unwrap().clone();
        let mut latencies: Vec<f64> = moved
            .iter()
            .filter_map(|(key, t)| arrivals.get(key).map(|a| a.duration_since(*t).as_secs_f64() * 1000.0))
            .collect();
        latencies.sort_by(f64::total_cmp);
        let a_commands = (stats.commands - stats0.commands) as f64 / elapsed;
        // Redis's own counts cover both servers (B sends its heartbeat too, and each INFO here is
        // one command): A's share is the total less B's, which is the same with any W.
        let total_commands = (cmd1 - cmd0) as f64 / elapsed;
        let a_in = (in1 - in0) as f64 / elapsed / 1024.0;
        let out_each = (out1 - out0) as f64 / elapsed / 1024.0 / 2.0; // two subscribers
        println!(
            "{walkers:7} | {a_commands:6.1} (Redis: {total_commands:.1} for both) | {a_in:8.1} (both) | {out_each:8.1} | {:.2} / {:.2} | {}",
            quantile(&latencies, 0.5),
            quantile(&latencies, 0.99),
            latencies.len()
        );
        world_a.leave().await;
        world_b.leave().await;
        tokio::time::sleep(Duration::from_millis(200)).await;
    }
}
