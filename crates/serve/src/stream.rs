//! The TCP stream under one SSH connection, wrapped: it counts the bytes each way (for the disconnect
//! log line) and can be cut from outside ([`Cut::cut`]) — which the server does when a client is too
//! slow to start, stops reading, or the server shuts down. A cut fails every later read and write and
//! wakes the one in progress, so the SSH library's own task ends at once even if it was blocked on a
//! client that reads nothing.

use std::io;
use std::pin::Pin;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::task::{Context, Poll, Waker};

use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};
use tokio::sync::watch;

/// The outside handle of a [`CutStream`]: its byte counts and its cut.
#[derive(Debug)]
pub(crate) struct Cut {
    cut: AtomicBool,
    /// Turns true at the cut, for tasks that wait on other things meanwhile ([`Cut::cut_off`]).
    signal: watch::Sender<bool>,
    wakers: Mutex<[Option<Waker>; 2]>,
    /// Bytes read from the client.
    pub bytes_in: AtomicU64,
    /// Bytes written to the client.
    pub bytes_out: AtomicU64,
}

impl Default for Cut {
    fn default() -> Self {
        Cut {
            cut: AtomicBool::new(false),
            signal: watch::Sender::new(false),
            wakers: Mutex::default(),
            bytes_in: AtomicU64::new(0),
            bytes_out: AtomicU64::new(0),
        }
    }
}

impl Cut {
    /// Cuts the stream: every read and write from now on fails, and any waiting one wakes.
    pub fn cut(&self) {
        self.cut.store(true, Ordering::SeqCst);
        let wakers = std::mem::take(&mut *self.wakers.lock().unwrap_or_else(PoisonError::into_inner));
        wakers.into_iter().flatten().for_each(Waker::wake);
        self.signal.send_replace(true);
    }

    /// Returns once the stream is cut: for a task waiting on something else (a write to a channel
    /// whose client reads nothing), which must give up when the connection is gone.
    pub async fn cut_off(&self) {
        let mut cut = self.signal.subscribe();
        let _ = cut.wait_for(|&c| c).await.is_ok(); // the guard is dropped here
    }

    /// Whether [`cut`](Self::cut) was called.
    #[must_use]
    pub(crate) fn is_cut(&self) -> bool {
        self.cut.load(Ordering::SeqCst)
    }

    /// Fails if cut; else remembers `cx`'s waker in `slot` (0 read, 1 write) for a cut to wake.
    fn check(&self, cx: &Context<'_>, slot: usize) -> io::Result<()> {
        let mut wakers = self.wakers.lock().unwrap_or_else(PoisonError::into_inner);
        if self.is_cut() {
            return Err(io::Error::new(io::ErrorKind::ConnectionAborted, "connection cut by the server"));
        }
        wakers[slot] = Some(cx.waker().clone());
        Ok(())
    }
}

/// A stream that counts its bytes and can be cut.
#[derive(Debug)]
pub(crate) struct CutStream<S> {
    inner: S,
    cut: Arc<Cut>,
}

impl<S> CutStream<S> {
    /// Wraps `inner`; the returned [`Cut`] counts and cuts it.
    pub fn new(inner: S) -> (CutStream<S>, Arc<Cut>) {
        let cut = Arc::new(Cut::default());
        (CutStream { inner, cut: Arc::clone(&cut) }, cut)
    }
}

impl<S: AsyncRead + Unpin> AsyncRead for CutStream<S> {
    fn poll_read(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &mut ReadBuf<'_>,
    ) -> Poll<io::Result<()>> {
        self.cut.check(cx, 0)?;
        let before = buf.filled().len();
        let polled = Pin::new(&mut self.inner).poll_read(cx, buf);
        self.cut.bytes_in.fetch_add((buf.filled().len() - before) as u64, Ordering::Relaxed);
        polled
    }
}

impl<S: AsyncWrite + Unpin> AsyncWrite for CutStream<S> {
    fn poll_write(mut self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &[u8]) -> Poll<io::Result<usize>> {
        self.cut.check(cx, 1)?;
        let polled = Pin::new(&mut self.inner).poll_write(cx, buf);
        if let Poll::Ready(Ok(n)) = polled {
            self.cut.bytes_out.fetch_add(n as u64, Ordering::Relaxed);
        }
        polled
    }

    fn poll_flush(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        self.cut.check(cx, 1)?;
        Pin::new(&mut self.inner).poll_flush(cx)
    }

    fn poll_shutdown(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.inner).poll_shutdown(cx)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tokio::io::{AsyncReadExt as _, AsyncWriteExt as _};

    #[tokio::test]
    async fn a_cut_wakes_a_blocked_read_and_counts_stay() {
        let (client, server) = tokio::io::duplex(64);
        let (mut stream, cut) = CutStream::new(server);
        let mut client = client;
        client.write_all(b"hello").await.unwrap();
        let mut buf = [0u8; 5];
        stream.read_exact(&mut buf).await.unwrap();
        stream.write_all(b"hi").await.unwrap();
        let reader = tokio::spawn(async move {
            let mut buf = [0u8; 1];
            stream.read(&mut buf).await // blocks: the client sends nothing more
        });
        tokio::task::yield_now().await;
        let waiter = {
            let cut = Arc::clone(&cut);
            tokio::spawn(async move { cut.cut_off().await })
        };
        cut.cut();
        let read = tokio::time::timeout(std::time::Duration::from_secs(5), reader).await.unwrap().unwrap();
        tokio::time::timeout(std::time::Duration::from_secs(5), waiter).await.unwrap().unwrap();
        cut.cut_off().await; // after the cut: at once
        assert_eq!(read.unwrap_err().kind(), io::ErrorKind::ConnectionAborted);
        assert_eq!((cut.bytes_in.load(Ordering::Relaxed), cut.bytes_out.load(Ordering::Relaxed)), (5, 2));
    }
}
