//! The process's processor time (`cfe::output::memory::cpu_seconds`), alone in
//! its own test binary: the count is the whole process's, so no other test may
//! run beside it.

use cfe::output::memory::cpu_seconds;

/// A chain of 60 million dependent multiplications: the same work each call.
fn work() -> f64 {
    let mut x = 1.0f64;
    for _ in 0..60_000_000 {
        x = std::hint::black_box(x * 1.000_000_1);
    }
    x
}

/// The same work done by two threads at once costs about twice the processor
/// time of one thread doing it (whichever cores they get): the count covers
/// every thread of the process, not only the caller.
#[test]
fn cpu_time_counts_every_thread() {
    let before = cpu_seconds().expect("getrusage on Unix");
    work();
    let one = cpu_seconds().unwrap() - before;
    assert!(one > 0.01, "one thread: {one} s");
    let before = cpu_seconds().unwrap();
    std::thread::scope(|s| {
        let other = s.spawn(work);
        work();
        other.join().unwrap();
    });
    let two = cpu_seconds().unwrap() - before;
    assert!(
        two > 1.5 * one && two < 4.0 * one,
        "two threads: {two} s, one: {one} s"
    );
}
