//! The TCP stream under one SSH connection, wrapped: it counts the bytes each way (for the disconnect
//! log line) and can be cut from outside ([`Cut::cut`]) — which the server does when a client is too
//! slow to start, stops reading, or the server shuts down. A cut fails every later read and write and
//! wakes the one in progress, so the SSH library's own task ends at once even if it was blocked on a
//! client that reads nothing.
//!
//! It also clocks the key exchange's CPU time ([`Cut::kex_finished`]): russh runs each connection in
//! a task of its own, out of the server's reach, but that task reads and writes through this stream.
//! From a read or write that returned ready to the task's next call here, on the same thread, the
//! library is working on what it read (or on what it sends next): the thread's CPU clock
//! (`CLOCK_THREAD_CPUTIME_ID`) between the two is that work. A call that returned pending starts no
//! interval (the thread may run other tasks before the next call), nor does a call on another
//! thread; the CPU time inside the calls (the system calls) is not counted.

use std::io;
use std::pin::Pin;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::task::{Context, Poll, Waker};
use std::thread::ThreadId;
use std::time::Duration;

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
    /// The key exchange's clock, until [`Cut::kex_finished`].
    kex: Mutex<KexClock>,
    /// Whether [`Cut::kex_finished`] was called: the clock is read no more.
    kex_over: AtomicBool,
}

/// The CPU time the SSH library's task spent on a connection between its calls to the stream.
#[derive(Debug, Default)]
struct KexClock {
    /// The thread and its CPU clock when a call last returned ready.
    since: Option<(ThreadId, Duration)>,
    spent: Duration,
}

/// This thread's CPU time so far (`None` where there is no such clock).
fn thread_cpu() -> Option<Duration> {
    #[cfg(unix)]
    {
        cpu_time::ThreadTime::try_now().ok().map(|now| now.as_duration())
    }
    #[cfg(not(unix))]
    None
}

impl Default for Cut {
    fn default() -> Self {
        Cut {
            cut: AtomicBool::new(false),
            signal: watch::Sender::new(false),
            wakers: Mutex::default(),
            bytes_in: AtomicU64::new(0),
            bytes_out: AtomicU64::new(0),
            kex: Mutex::default(),
            kex_over: AtomicBool::new(false),
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

    /// The key exchange is over (or the connection is): the CPU time the SSH library spent on the
    /// connection until now, between its calls to the stream (see the module's doc). `None` after the
    /// first call: the clock stops there.
    pub fn kex_finished(&self) -> Option<Duration> {
        if self.kex_over.swap(true, Ordering::SeqCst) {
            return None;
        }
        Some(self.kex.lock().unwrap_or_else(PoisonError::into_inner).spent)
    }

    /// A call to the stream begins: the library's work since the last ready call ends here.
    fn kex_enter(&self) {
        if self.kex_over.load(Ordering::Relaxed) {
            return;
        }
        let mut clock = self.kex.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some((thread, at)) = clock.since.take()
            && thread == std::thread::current().id()
            && let Some(now) = thread_cpu()
        {
            clock.spent += now.saturating_sub(at);
        }
    }

    /// A call to the stream returns: if ready, the library's work on its outcome begins.
    fn kex_leave<T>(&self, polled: &Poll<T>) {
        if self.kex_over.load(Ordering::Relaxed) {
            return;
        }
        let since = match polled {
            Poll::Ready(_) => thread_cpu().map(|now| (std::thread::current().id(), now)),
            Poll::Pending => None,
        };
        self.kex.lock().unwrap_or_else(PoisonError::into_inner).since = since;
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
        self.cut.kex_enter();
        let before = buf.filled().len();
        let polled = Pin::new(&mut self.inner).poll_read(cx, buf);
        self.cut.bytes_in.fetch_add((buf.filled().len() - before) as u64, Ordering::Relaxed);
        self.cut.kex_leave(&polled);
        polled
    }
}

impl<S: AsyncWrite + Unpin> AsyncWrite for CutStream<S> {
    fn poll_write(mut self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &[u8]) -> Poll<io::Result<usize>> {
        self.cut.check(cx, 1)?;
        self.cut.kex_enter();
        let polled = Pin::new(&mut self.inner).poll_write(cx, buf);
        if let Poll::Ready(Ok(n)) = polled {
            self.cut.bytes_out.fetch_add(n as u64, Ordering::Relaxed);
        }
        self.cut.kex_leave(&polled);
        polled
    }

    fn poll_flush(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        self.cut.check(cx, 1)?;
        self.cut.kex_enter();
        let polled = Pin::new(&mut self.inner).poll_flush(cx);
        self.cut.kex_leave(&polled);
        polled
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

    /// Spins on this thread until its CPU clock has advanced by `cpu`.
    fn burn(cpu: Duration) {
        let start = thread_cpu().expect("a thread CPU clock");
        while thread_cpu().expect("a thread CPU clock") - start < cpu {
            std::hint::black_box(0u64);
        }
    }

    /// The library's work between a ready read and its next write is the key exchange's CPU time;
    /// once read, the clock stops.
    #[tokio::test(flavor = "current_thread")]
    async fn work_between_a_ready_read_and_the_next_call_is_clocked() {
        let (mut client, server) = tokio::io::duplex(64);
        let (mut stream, cut) = CutStream::new(server);
        client.write_all(b"kexinit").await.unwrap();
        let mut buf = [0u8; 7];
        stream.read_exact(&mut buf).await.unwrap();
        burn(Duration::from_millis(30)); // "the key exchange"
        stream.write_all(b"reply").await.unwrap();
        let spent = cut.kex_finished().expect("the first reading");
        assert!(spent >= Duration::from_millis(30) && spent < Duration::from_secs(2), "{spent:?}");
        assert_eq!(cut.kex_finished(), None, "read once");
        stream.write_all(b"later").await.unwrap();
        assert_eq!(cut.kex_finished(), None);
    }

    /// What the thread does while a read is pending (other tasks' work) is not the connection's.
    #[tokio::test(flavor = "current_thread")]
    async fn work_while_a_read_is_pending_is_not_clocked() {
        let (mut client, server) = tokio::io::duplex(64);
        let (mut stream, cut) = CutStream::new(server);
        let reader = tokio::spawn(async move {
            let mut buf = [0u8; 1];
            stream.read_exact(&mut buf).await.unwrap(); // pending at first: nothing sent yet
            (stream, cut.kex_finished().expect("the first reading"))
        });
        tokio::task::yield_now().await; // the reader polls, and waits
        burn(Duration::from_millis(50)); // another task's work, on the same thread
        client.write_all(b"x").await.unwrap();
        let (_stream, spent) = reader.await.unwrap();
        assert!(spent < Duration::from_millis(25), "{spent:?} counted");
    }
}
