//! `serve --http ADDR`: a small HTTP/1.1 listener beside the SSH one, on the same tokio runtime
//! (hyper 1). It serves `/metrics` ([`metrics`](crate::metrics)) and nothing else yet; every other
//! path is 404, every method but GET and HEAD 405.
//!
//! Bounded like the SSH side, whoever connects:
//! - at most [`MAX_CONNECTIONS`] connections at once; past it a newcomer is closed at once;
//! - the request's head within [`HEADER_TIMEOUT`] (a slowloris client is cut), at most
//!   [`MAX_HEAD_BYTES`] of it (hyper answers 431 past that), and a connection lives
//!   [`CONNECTION_LIFETIME`] at most, keep-alive or not;
//! - request bodies are never read.

use std::convert::Infallible;
use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use http_body_util::Full;
use hyper::body::{Bytes, Incoming};
use hyper::{Method, Request, Response, StatusCode};
use hyper_util::rt::{TokioIo, TokioTimer};
use prometheus_client::registry::Registry;
use tokio::net::TcpListener;
use tokio::sync::watch;

/// Connections at once, at most.
pub const MAX_CONNECTIONS: usize = 64;
/// How long a client has to send a request's head.
pub const HEADER_TIMEOUT: Duration = Duration::from_secs(5);
/// The longest a connection stays open.
pub const CONNECTION_LIFETIME: Duration = Duration::from_secs(60);
/// The most bytes of a request's head (hyper's read buffer; its least is 8 KiB).
pub const MAX_HEAD_BYTES: usize = 16 * 1024;

/// What the listener serves.
pub(crate) struct Site {
    /// Encoded at each scrape of `/metrics`.
    pub registry: Registry,
}

/// Binds `addr` and serves `site` until `shutdown` turns true; returns the bound address and the task.
///
/// # Errors
/// The address cannot be bound.
pub(crate) async fn start(
    addr: SocketAddr,
    site: Site,
    shutdown: watch::Receiver<bool>,
) -> std::io::Result<(SocketAddr, tokio::task::JoinHandle<()>)> {
    let listener = TcpListener::bind(addr)
        .await
        .map_err(|e| std::io::Error::new(e.kind(), format!("--http: cannot listen on {addr}: {e}")))?;
    let local = listener.local_addr()?;
    let task = tokio::spawn(accept_loop(listener, Arc::new(site), shutdown));
    Ok((local, task))
}

async fn accept_loop(listener: TcpListener, site: Arc<Site>, mut shutdown: watch::Receiver<bool>) {
    let open = Arc::new(AtomicUsize::new(0));
    loop {
        let accepted = tokio::select! {
            _ = shutdown.wait_for(|&s| s) => return,
            accepted = listener.accept() => accepted,
        };
        let Ok((stream, _)) = accepted else {
            // Out of descriptors, say: wait a little rather than spin.
            tokio::time::sleep(Duration::from_millis(100)).await;
            continue;
        };
        if open.load(Ordering::SeqCst) >= MAX_CONNECTIONS {
            drop(stream); // closed unanswered: the cap holds whatever the clients do
            continue;
        }
        open.fetch_add(1, Ordering::SeqCst);
        let guard = Open(Arc::clone(&open));
        let site = Arc::clone(&site);
        let mut shutdown = shutdown.clone();
        tokio::spawn(async move {
            let _guard = guard;
            let service = hyper::service::service_fn(move |request| {
                let site = Arc::clone(&site);
                async move { Ok::<_, Infallible>(answer(&site, &request)) }
            });
            let connection = hyper::server::conn::http1::Builder::new()
                .timer(TokioTimer::new())
                .header_read_timeout(HEADER_TIMEOUT)
                .max_buf_size(MAX_HEAD_BYTES)
                .serve_connection(TokioIo::new(stream), service);
            tokio::select! {
                _ = tokio::time::timeout(CONNECTION_LIFETIME, connection) => {}
                _ = shutdown.wait_for(|&s| s) => {}
            }
        });
    }
}

/// Counts an open connection while it lives.
struct Open(Arc<AtomicUsize>);

impl Drop for Open {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

fn answer(site: &Site, request: &Request<Incoming>) -> Response<Full<Bytes>> {
    let respond = |status: StatusCode, content_type: &str, body: String| {
        let body = if request.method() == Method::HEAD { Bytes::new() } else { Bytes::from(body) };
        let mut response = Response::new(Full::new(body));
        *response.status_mut() = status;
        if let Ok(value) = content_type.parse() {
            response.headers_mut().insert(hyper::header::CONTENT_TYPE, value);
        }
        response
    };
    if !matches!(*request.method(), Method::GET | Method::HEAD) {
        let mut response = respond(StatusCode::METHOD_NOT_ALLOWED, "text/plain", "GET or HEAD only\n".into());
        response
            .headers_mut()
            .insert(hyper::header::ALLOW, hyper::header::HeaderValue::from_static("GET, HEAD"));
        return response;
    }
    match request.uri().path() {
        "/metrics" => {
            respond(StatusCode::OK, crate::metrics::CONTENT_TYPE, crate::metrics::encode(&site.registry))
        }
        _ => respond(StatusCode::NOT_FOUND, "text/plain", "not found: try /metrics\n".into()),
    }
}
