//! Where the end-to-end jobs run: a temporary output directory and a
//! silenced standard output.

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A directory under the system's temporary directory, removed on drop.
pub(super) struct TempDir(pub(super) PathBuf);

impl TempDir {
    pub(super) fn new() -> std::io::Result<TempDir> {
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        let path = std::env::temp_dir().join(format!(
            "stickslip-bench-{}-{}",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir_all(&path)?;
        Ok(TempDir(path))
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Runs `f` with the process's standard output (file descriptor 1) sent to
/// `/dev/null`, so that a command's report does not mix with the benchmark's.
/// Printing still happens (and is timed); only its destination changes.
/// (Not in unit tests: there the test harness captures `println!` itself,
/// and redirecting descriptor 1 would swallow its reports of other tests.)
#[cfg(all(unix, not(test)))]
pub(super) fn silence_stdout<T>(f: impl FnOnce() -> T) -> T {
    use std::io::Write;
    struct Restore(libc::c_int);
    impl Drop for Restore {
        fn drop(&mut self) {
            let _ = std::io::stdout().flush();
            // SAFETY: `self.0` is a descriptor duplicated from 1 below and
            // owned here; dup2 and close on valid descriptors.
            unsafe {
                libc::dup2(self.0, 1);
                libc::close(self.0);
            }
        }
    }
    let _ = std::io::stdout().flush();
    // SAFETY: plain descriptor calls; every descriptor opened here is closed
    // (the saved one by `Restore`), and 1 is restored even if `f` panics.
    let _restore = unsafe {
        let null = libc::open(c"/dev/null".as_ptr(), libc::O_WRONLY);
        if null < 0 {
            return f();
        }
        let saved = libc::dup(1);
        if saved < 0 {
            libc::close(null);
            return f();
        }
        libc::dup2(null, 1);
        libc::close(null);
        Restore(saved)
    };
    f()
}

#[cfg(not(all(unix, not(test))))]
pub(super) fn silence_stdout<T>(f: impl FnOnce() -> T) -> T {
    f()
}
