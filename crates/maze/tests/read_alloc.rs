//! A maze file's read allocates as the data arrives, never by what the file's size claims: a file of
//! a text head and then zero bytes costs its head, not its length. Its own test binary, since it
//! counts every allocation of the process (the largest one asked for): a global allocator, which
//! takes `unsafe`.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Largest;

static LARGEST: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is passed on to `System` unchanged; the counter only records sizes.
unsafe impl GlobalAlloc for Largest {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        // SAFETY: the caller's contract, passed on.
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        // SAFETY: the caller's contract, passed on.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract, passed on.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LARGEST.fetch_max(new_size, Ordering::Relaxed);
        // SAFETY: the caller's contract, passed on.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOC: Largest = Largest;

#[test]
fn a_text_head_then_zeros_is_read_only_as_far_as_the_zeros() {
    const MIB: usize = 1 << 20;
    let dir = std::env::temp_dir().join(format!("mazewalk-read-alloc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("zeros.grid");
    // a grid file's first line and 1.5 MiB of wall rows, then 62.5 MiB of zero bytes
    let mut bytes = b"mazewalk-grid 1\n".to_vec();
    while bytes.len() < 3 * MIB / 2 {
        bytes.extend_from_slice(&[b'#'; 1023]);
        bytes.push(b'\n');
    }
    let text = bytes.len();
    bytes.resize(64 * MIB, 0);
    std::fs::write(&path, &bytes).unwrap();
    drop(bytes);

    LARGEST.store(0, Ordering::Relaxed);
    let error = mazewalk_maze::load(&path).unwrap_err().to_string();
    let largest = LARGEST.load(Ordering::Relaxed);
    std::fs::remove_dir_all(&dir).unwrap();

    assert!(error.contains("a NUL byte"), "{error}");
    // the text and the chunk the first zero is in, as a buffer that doubles: under 2× of it
    assert!(largest < 2 * (text + MIB), "largest allocation {largest} bytes for {text} bytes of text");
}
