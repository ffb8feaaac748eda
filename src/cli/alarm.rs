//! The time budget's alarm on Unix: the kernel's interval timer (`setitimer`, real time) and a
//! `SIGALRM` handler, instead of a thread that sleeps.
//!
//! Starting a thread (its stack mapped, cloned, scheduled, and killed at exit) cost about
//! 0.06 ms of CPU per process on the 2-core machine — a 10-state `gain --summary` took
//! 0.357 ms above the process floor with the thread, 0.287 ms with the alarm (300 interleaved
//! runs, minimum); arming a timer is two system calls. The handler may only do what is safe inside a signal handler, so what it
//! prints is rendered before the timer is armed: it claims the end of the command (an atomic
//! exchange), writes the prepared bytes with `write(2)` and leaves with `_exit(2)`.
//!
//! Cost: two system calls to arm, one to disarm. Identity: the bytes and the status are those
//! the finished command's error path gives for [`super::Stopped::TimeBudget`].
//!
//! One of the project's two modules with `unsafe` (with the allocator, `large_pages`; the
//! crate denies it everywhere else): four calls into the C library and the read of the leaked
//! ending, each with the reason it is sound beside it.
#![allow(unsafe_code)]

use std::sync::atomic::{AtomicPtr, Ordering};

/// What the handler prints: standard output's bytes, then standard error's.
struct Prepared {
    out: Box<[u8]>,
    err: Box<[u8]>,
}

/// The prepared ending, leaked once per process (a command arms the alarm once); null before.
static PREPARED: AtomicPtr<Prepared> = AtomicPtr::new(std::ptr::null_mut());

/// Writes all of `bytes` to descriptor `fd` (retrying short writes and interruptions): the
/// `errno` of a failure, if any.
fn write_all(fd: libc::c_int, mut bytes: &[u8]) -> Result<(), libc::c_int> {
    while !bytes.is_empty() {
        // SAFETY: `bytes` is a live slice; write(2) is async-signal-safe.
        let n = unsafe { libc::write(fd, bytes.as_ptr().cast(), bytes.len()) };
        if n < 0 {
            let errno = std::io::Error::last_os_error().raw_os_error().unwrap_or(0);
            if errno == libc::EINTR {
                continue;
            }
            return Err(errno);
        }
        bytes = &bytes[n.unsigned_abs().min(bytes.len())..];
    }
    Ok(())
}

/// The `SIGALRM` handler: when the command has not finished first, the budget's error is
/// printed and the process ends (status 2, or 141 when standard output's reader is gone).
extern "C" fn on_alarm(_signal: libc::c_int) {
    if !super::Race::claim(super::Race::TimedOut) {
        return;
    }
    // SAFETY: the pointer is null or was leaked by `arm` before the timer was armed, and lives
    // to the end of the process.
    let prepared = unsafe { PREPARED.load(Ordering::SeqCst).as_ref() };
    let (out, err) = prepared.map_or((&[][..], &[][..]), |p| (&p.out[..], &p.err[..]));
    let status = match write_all(libc::STDOUT_FILENO, out) {
        Err(libc::EPIPE) => 141,
        Ok(()) | Err(_) => 2,
    };
    let _ = write_all(libc::STDERR_FILENO, err);
    // SAFETY: _exit(2) is async-signal-safe; nothing is left to flush (the command printed
    // nothing before it finished).
    unsafe { libc::_exit(status) }
}

/// Arms the alarm: after `budget` seconds (at least a microsecond) of real time, `out` goes to
/// standard output, `err` to standard error, and the process ends — unless the command has
/// claimed its end first ([`super::Race::claim`]).
pub fn arm(budget: f64, out: String, err: String) -> std::io::Result<()> {
    let prepared = Box::new(Prepared {
        out: out.into_bytes().into_boxed_slice(),
        err: err.into_bytes().into_boxed_slice(),
    });
    PREPARED.store(Box::leak(prepared), Ordering::SeqCst);
    // SAFETY: a zeroed sigaction is a valid empty one; the handler only does
    // async-signal-safe work; SA_RESTART resumes system calls the signal interrupts.
    unsafe {
        let mut action: libc::sigaction = std::mem::zeroed();
        action.sa_sigaction = on_alarm as extern "C" fn(libc::c_int) as libc::sighandler_t;
        action.sa_flags = libc::SA_RESTART;
        libc::sigemptyset(&mut action.sa_mask);
        if libc::sigaction(libc::SIGALRM, &action, std::ptr::null_mut()) != 0 {
            return Err(std::io::Error::last_os_error());
        }
    }
    set_timer(budget.max(1e-6))
}

/// Disarms the alarm (the command finished first).
pub fn disarm() {
    let _ = set_timer(0.0);
}

/// Sets the real-time interval timer to fire once after `seconds` (0: never).
fn set_timer(seconds: f64) -> std::io::Result<()> {
    let whole = seconds.trunc();
    let timer = libc::itimerval {
        it_interval: libc::timeval {
            tv_sec: 0,
            tv_usec: 0,
        },
        it_value: libc::timeval {
            // at most 2 × 86 400 s (checked by the caller): within time_t
            tv_sec: whole as libc::time_t,
            tv_usec: (((seconds - whole) * 1e6).ceil() as libc::suseconds_t).min(999_999),
        },
    };
    // SAFETY: `timer` is a valid itimerval; the old value is not asked for.
    if unsafe { libc::setitimer(libc::ITIMER_REAL, &timer, std::ptr::null_mut()) } != 0 {
        return Err(std::io::Error::last_os_error());
    }
    Ok(())
}
