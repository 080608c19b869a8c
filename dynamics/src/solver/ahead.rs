//! A worker thread that runs ahead of a stepping loop, on another core.
//!
//! Step `k` of the loop reads data that depend on `k` alone (the monolithic step's
//! geometry: where the wheelsets are, the rail shapes and the track under them). The worker
//! makes them for the steps after `k` while the loop works on step `k`, in a ring of `N`
//! slots: it fills slot `k mod N` for step `k` once the loop has handed back the slot of step
//! `k − N`, and the loop takes slot `k mod N` once the worker has filled it. Either side
//! waits by spinning for a while (a step takes microseconds, far less than waking a sleeping
//! thread), then sleeps until the other wakes it (each says when it goes to sleep, so the
//! other makes the system call only then; the worker sleeps until half the ring is free).
//!
//! What the two sides share sits in cache lines of its own, the counters each in one, and
//! each side keeps the other's counter as last read, reading it again only when it has to
//! wait: on a virtual machine a cache line crossing between the cores can cost as much as a
//! few hundred instructions.

use std::cell::UnsafeCell;
use std::sync::atomic::{fence, AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::{self, JoinHandle, Thread};
use std::time::{Duration, Instant};

/// How long a loop that gives up waits at most for a slot (`Ahead::spawn`'s `give_up`):
/// a worker that falls this far behind has no core of its own (another process runs on
/// it), and the loop is better off alone. Without other load on the machine the loop of the
/// bench case waited for its slot a few times in 22 378 steps, up to about a millisecond in
/// all; with one other busy process on a machine of two cores a run whose geometry was made
/// ahead took three times as long.
pub const MAX_LAG: Duration = Duration::from_millis(2);

/// How long the loop spins before it sleeps.
const SPIN: Duration = Duration::from_micros(200);

/// How long the worker spins on a full ring before it sleeps: waking it costs the loop a
/// system call, and in a virtual machine an interrupt between the cores, several steps'
/// worth.
const WORKER_SPIN: Duration = Duration::from_millis(2);

/// A value alone in its cache lines, so that one side's writes to it never take a line the
/// other side's data sit in.
#[repr(align(128))]
struct Padded<T>(T);

struct Shared<T> {
    /// The ring: step `k`'s slot `k mod N` is the worker's while `filled ≤ k < returned +
    /// N`, and the loop's while `returned ≤ k < filled` (the counters below), so one side's
    /// at a time.
    slots: Vec<Padded<UnsafeCell<T>>>,
    /// Steps filled by the worker (written by the worker alone).
    filled: Padded<AtomicU64>,
    /// Slots handed back by the loop: those of the steps before this count (written by the
    /// loop alone).
    returned: Padded<AtomicU64>,
    /// The loop has dropped its end, or the worker has stopped (its fill panicked).
    closed: Padded<AtomicBool>,
    /// The worker sleeps until `returned ≥ wake_at`.
    worker_sleeps: Padded<AtomicBool>,
    wake_at: Padded<AtomicU64>,
    /// The loop sleeps until `filled` passes its step.
    loop_sleeps: Padded<AtomicBool>,
    /// The loop's thread, woken when it sleeps and a slot is filled.
    consumer: Mutex<Thread>,
}

// SAFETY: a slot is written by the worker alone between its being handed back and filled,
// and read (and written) by the loop alone between its being filled and handed back; the
// counters' release stores and acquire loads order the two (see `Shared::slots`).
unsafe impl<T: Send> Sync for Shared<T> {}

impl<T> Shared<T> {
    fn slot(&self, k: u64) -> *mut T {
        self.slots[(k % self.slots.len() as u64) as usize].0.get()
    }

    /// Wait until `ready()`: spin for `spin`, then sleep with `sleeps` set. False when the
    /// ring closes first, or when `give_up` has passed.
    fn wait(
        &self,
        sleeps: &AtomicBool,
        spin: Duration,
        give_up: Option<Duration>,
        ready: impl Fn() -> bool,
    ) -> bool {
        let start = Instant::now();
        let mut spins = 0u32;
        loop {
            if ready() {
                return true;
            }
            if self.closed.0.load(Ordering::Acquire) {
                return ready();
            }
            spins = spins.wrapping_add(1);
            // no `spin_loop` hint: in a virtual machine a loop of pause instructions may
            // make the host take the core, which the other side then waits for
            if spins & 63 != 0 {
                continue;
            }
            let waited = start.elapsed();
            if give_up.is_some_and(|g| waited >= g) {
                return ready();
            }
            if waited < spin {
                continue;
            }
            sleeps.store(true, Ordering::SeqCst);
            fence(Ordering::SeqCst);
            if !ready() && !self.closed.0.load(Ordering::SeqCst) {
                // the other side, after its counter's store, sees `sleeps` and unparks (a
                // token given before the park makes it return at once); the timeout is a
                // guard, and the end of the wait
                let guard = Duration::from_millis(10);
                thread::park_timeout(
                    give_up.map_or(guard, |g| g.saturating_sub(waited).min(guard)),
                );
            }
            sleeps.store(false, Ordering::SeqCst);
        }
    }
}

/// The loop's end of the ring (see the module docs). Dropping it stops the worker.
pub struct Ahead<T> {
    shared: Arc<Shared<T>>,
    worker: Option<JoinHandle<()>>,
    /// The step whose slot the loop takes next; the loop holds the one before until then.
    next: u64,
    /// `filled` as last read (the loop reads the counter only when its step passes this).
    filled: u64,
    /// The longest the loop waits for a slot.
    give_up: Option<Duration>,
}

impl<T: Send + 'static> Ahead<T> {
    /// Start the worker with the ring's `slots` (at least three); it calls `fill(k, slot)`
    /// for `k = 0, 1, 2, …` in order. What a slot holds is best allocated by the worker, in
    /// its first fill (the worker's allocations lie apart from the loop's). With `give_up`
    /// the loop waits at most that long for a slot ([`Ahead::next`]; [`MAX_LAG`]).
    pub fn spawn(
        slots: Vec<T>,
        give_up: Option<Duration>,
        mut fill: impl FnMut(u64, &mut T) + Send + 'static,
    ) -> std::io::Result<Self> {
        assert!(slots.len() >= 3, "a ring of at least three slots");
        let n = slots.len() as u64;
        let shared = Arc::new(Shared {
            slots: slots
                .into_iter()
                .map(|t| Padded(UnsafeCell::new(t)))
                .collect(),
            filled: Padded(AtomicU64::new(0)),
            returned: Padded(AtomicU64::new(0)),
            closed: Padded(AtomicBool::new(false)),
            worker_sleeps: Padded(AtomicBool::new(false)),
            wake_at: Padded(AtomicU64::new(0)),
            loop_sleeps: Padded(AtomicBool::new(false)),
            consumer: Mutex::new(thread::current()),
        });
        let s = shared.clone();
        let worker = thread::Builder::new()
            .name("tbi-ahead".into())
            .spawn(move || {
                /// Closes the ring when the worker ends, also by a panic, and wakes the loop.
                struct Close<T>(Arc<Shared<T>>);
                impl<T> Drop for Close<T> {
                    fn drop(&mut self) {
                        self.0.closed.0.store(true, Ordering::SeqCst);
                        self.0.consumer.lock().map(|c| c.unpark()).ok();
                    }
                }
                let close = Close(s);
                let s = &*close.0;
                let mut returned = 0;
                for k in 0.. {
                    if s.closed.0.load(Ordering::Relaxed) {
                        return;
                    }
                    if returned + n <= k {
                        returned = s.returned.0.load(Ordering::Acquire);
                    }
                    if returned + n <= k {
                        // the ring is full: spin until a slot is free; after WORKER_SPIN,
                        // sleep until half of the ring is
                        let at = k + 1 - n + (n / 2 - 1);
                        s.wake_at.0.store(at, Ordering::SeqCst);
                        let start = Instant::now();
                        let ready = || {
                            let r = s.returned.0.load(Ordering::Acquire);
                            r + n > k && (r >= at || start.elapsed() < WORKER_SPIN)
                        };
                        if !s.wait(&s.worker_sleeps.0, WORKER_SPIN, None, ready) {
                            return;
                        }
                        returned = s.returned.0.load(Ordering::Acquire);
                    }
                    // SAFETY: slot k is the worker's: the loop handed it back (k < returned
                    // + N, acquired) and has not been told it is filled (see `Shared`)
                    fill(k, unsafe { &mut *s.slot(k) });
                    s.filled.0.store(k + 1, Ordering::Release);
                    fence(Ordering::SeqCst);
                    if s.loop_sleeps.0.load(Ordering::Acquire) {
                        s.consumer.lock().map(|c| c.unpark()).ok();
                    }
                }
            })?;
        Ok(Ahead {
            shared,
            worker: Some(worker),
            next: 0,
            filled: 0,
            give_up,
        })
    }

    /// `f(held, slot)` with the next step's slot once the worker has filled it, and the
    /// slot of the step before (None at the first step), which then goes back to the worker:
    /// the loop holds a slot from this call to the next, so it may swap the slot's contents
    /// with its own and back. None, without calling `f`, when the worker has stopped before
    /// filling it, or has not filled it within the `give_up` time of [`Ahead::spawn`] (it
    /// lacks a core: another process has it); the ring is then of no further use.
    pub fn next<R>(&mut self, f: impl FnOnce(Option<&mut T>, &mut T) -> R) -> Option<R> {
        let s = &*self.shared;
        let k = self.next;
        if self.filled <= k {
            self.filled = s.filled.0.load(Ordering::Acquire);
        }
        if self.filled <= k {
            *s.consumer.lock().ok()? = thread::current();
            let ready = || s.filled.0.load(Ordering::Acquire) > k;
            if !s.wait(&s.loop_sleeps.0, SPIN, self.give_up, ready) {
                return None;
            }
            self.filled = s.filled.0.load(Ordering::Acquire);
        }
        // SAFETY: slot k is filled (k < filled, acquired) and not handed back, slot k − 1
        // was taken by the call before and not handed back: both are the loop's, and they
        // are two slots (N ≥ 3)
        let r = unsafe {
            let slot = &mut *s.slot(k);
            match k.checked_sub(1) {
                Some(held) => f(Some(&mut *s.slot(held)), slot),
                None => f(None, slot),
            }
        };
        self.next = k + 1;
        // the held slot goes back
        s.returned.0.store(k, Ordering::Release);
        fence(Ordering::SeqCst);
        if s.worker_sleeps.0.load(Ordering::Acquire) && k >= s.wake_at.0.load(Ordering::Relaxed) {
            if let Some(w) = &self.worker {
                w.thread().unpark();
            }
        }
        Some(r)
    }
}

impl<T> Drop for Ahead<T> {
    fn drop(&mut self) {
        self.shared.closed.0.store(true, Ordering::SeqCst);
        if let Some(w) = self.worker.take() {
            w.thread().unpark();
            // a panic of the worker has already closed the ring; nothing to report here
            let _ = w.join();
        }
    }
}

impl<T> std::fmt::Debug for Ahead<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ahead")
            .field("slots", &self.shared.slots.len())
            .field("next", &self.next)
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_loop_gets_every_step_in_order() {
        let mut a = Ahead::spawn(vec![0u64; 3], None, |k, s| *s = k * k).unwrap();
        for k in 0..10_000u64 {
            let held = k.checked_sub(1).map(|h| h * h);
            assert_eq!(a.next(|h, s| (h.map(|h| *h), *s)), Some((held, k * k)));
        }
    }

    #[test]
    fn a_slow_loop_and_a_slow_worker_lose_nothing() {
        let mut a = Ahead::spawn(vec![0u64; 3], None, |k, s| {
            if k % 7 == 0 {
                thread::sleep(Duration::from_micros(500));
            }
            *s = k + 1;
        })
        .unwrap();
        for k in 0..200u64 {
            if k % 5 == 0 {
                thread::sleep(Duration::from_micros(700));
            }
            assert_eq!(a.next(|_, s| *s), Some(k + 1));
        }
    }

    #[test]
    fn a_worker_far_behind_ends_the_ring() {
        // The worker fills steps 0 to 4 and then stalls at step 5 until released: the loop
        // takes the five, then gives up on step 5 after MAX_LAG, while the worker is still
        // stalled (no bound on the loop's wait beyond that: on a loaded machine a thread
        // may wait for its core any time).
        let made = Arc::new(AtomicU64::new(0));
        let release = Arc::new(AtomicBool::new(false));
        let (m, r) = (made.clone(), release.clone());
        let mut a = Ahead::spawn(vec![0u64; 6], Some(MAX_LAG), move |k, s| {
            if k == 5 {
                // a guard against a test that fails before it releases the worker
                let start = Instant::now();
                while !r.load(Ordering::Acquire) && start.elapsed() < Duration::from_secs(30) {
                    thread::sleep(Duration::from_millis(1));
                }
            }
            *s = k;
            m.store(k + 1, Ordering::Release);
        })
        .unwrap();
        let start = Instant::now();
        while made.load(Ordering::Acquire) < 5 {
            assert!(
                start.elapsed() < Duration::from_secs(30),
                "the worker never ran"
            );
            thread::sleep(Duration::from_millis(1));
        }
        for k in 0..5 {
            assert_eq!(a.next(|_, s| *s), Some(k));
        }
        let start = Instant::now();
        assert_eq!(a.next(|_, s| *s), None);
        let waited = start.elapsed();
        assert!(waited >= MAX_LAG, "{waited:?}");
        assert_eq!(
            made.load(Ordering::Acquire),
            5,
            "the worker was still stalled"
        );
        release.store(true, Ordering::Release);
    }

    #[test]
    fn a_worker_that_panics_ends_the_ring() {
        let mut a = Ahead::spawn(vec![0u64; 3], None, |k, s| {
            assert!(k < 5, "the fill fails at step 5");
            *s = k;
        })
        .unwrap();
        for k in 0..5 {
            assert_eq!(a.next(|_, s| *s), Some(k));
        }
        assert_eq!(a.next(|_, s| *s), None);
        assert_eq!(a.next(|_, s| *s), None);
    }
}
