//! One observer shape for every iterative algorithm of mrbrake.
//!
//! Brief overview: an algorithm that runs in steps (a time integrator's accepted steps, a current
//! sweep's points, an optimiser's generations, a study's designs, a Z-width map's rows) takes an
//! [`Observer`] of its own event type and calls [`Observer::observe`] once per event. The observer
//! answers with a [`Flow`]: [`Flow::Continue`], or [`Flow::Stop`] to ask the algorithm to stop
//! after this event (a cancelled study, a user's Ctrl-C, a browser edit that makes a running solve
//! obsolete). How an algorithm reports a stop is its own business (a truncated result, or an error
//! variant naming the event it stopped at); it never panics and never loses what it has finished.
//!
//! The shape follows argmin's observers (`argmin::core::observers::Observe`, called once per
//! iteration with the solver's state) with the termination request of `core::ops::ControlFlow`,
//! reduced to what mrbrake needs: one method, one event type per algorithm, no allocation (the
//! crate is `no_std`, so the real-time controller's crates may use it).
//!
//! - Any `FnMut(&Event) -> Flow` closure is an observer.
//! - [`Silent`] observes nothing.
//! - A pair `(a, b)` observes with both and stops when either asks.
//! - [`Count`] is the event of counted loops (`done` of `total`), e.g. the points of a sweep.
//!
//! An observer that can fail (say, a torque computed from every time step's field) keeps its error
//! and returns [`Flow::Stop`]; the caller, which owns the observer, returns that error after the
//! algorithm has stopped:
//!
//! ```
//! use mrbrake_observe::{Flow, Observer};
//!
//! /// A stand-in algorithm: ten steps, observed.
//! fn run(observer: &mut impl Observer<usize>) -> usize {
//!     for step in 1..=10 {
//!         if observer.observe(&step).is_stop() {
//!             return step;
//!         }
//!     }
//!     10
//! }
//!
//! let mut failure = None;
//! let stopped_at = run(&mut |step: &usize| {
//!     if *step == 4 {
//!         failure = Some("the probe left the mesh");
//!         return Flow::Stop;
//!     }
//!     Flow::Continue
//! });
//! assert_eq!(stopped_at, 4);
//! assert_eq!(failure, Some("the probe left the mesh"));
//! ```
#![no_std]
#![forbid(unsafe_code)]

/// What an observer asks of the algorithm after an event.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Flow {
    /// Go on.
    #[default]
    Continue,
    /// Stop after this event (keeping what is finished).
    Stop,
}

impl Flow {
    /// True for [`Flow::Stop`].
    pub const fn is_stop(self) -> bool {
        matches!(self, Self::Stop)
    }

    /// [`Flow::Stop`] when `stop` holds, else [`Flow::Continue`].
    pub const fn stop_if(stop: bool) -> Self {
        if stop { Self::Stop } else { Self::Continue }
    }

    /// Stop when either asks.
    pub const fn or(self, other: Self) -> Self {
        Self::stop_if(self.is_stop() || other.is_stop())
    }
}

/// Sees every event of an algorithm and may ask it to stop.
pub trait Observer<Event: ?Sized> {
    /// Called once per event (step, point, generation, design), in order.
    fn observe(&mut self, event: &Event) -> Flow;
}

impl<Event: ?Sized, F: FnMut(&Event) -> Flow> Observer<Event> for F {
    fn observe(&mut self, event: &Event) -> Flow {
        self(event)
    }
}

/// Observes nothing and never stops.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl<Event: ?Sized> Observer<Event> for Silent {
    fn observe(&mut self, _event: &Event) -> Flow {
        Flow::Continue
    }
}

/// Both observers see every event (the first, then the second); the algorithm stops when either
/// asks.
impl<Event: ?Sized, A: Observer<Event>, B: Observer<Event>> Observer<Event> for (A, B) {
    fn observe(&mut self, event: &Event) -> Flow {
        let first = self.0.observe(event);
        first.or(self.1.observe(event))
    }
}

/// The event of a counted loop: `done` of `total` items finished.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Count {
    /// Items finished so far (1 after the first).
    pub done: usize,
    /// Items in the whole loop.
    pub total: usize,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pair_stops_when_either_asks_and_both_see_every_event() {
        let (mut seen_a, mut seen_b) = (0, 0);
        {
            let a = |_: &Count| {
                seen_a += 1;
                Flow::Continue
            };
            let b = |c: &Count| {
                seen_b += 1;
                Flow::stop_if(c.done == 2)
            };
            let mut pair = (a, b);
            assert_eq!(pair.observe(&Count { done: 1, total: 3 }), Flow::Continue);
            assert_eq!(pair.observe(&Count { done: 2, total: 3 }), Flow::Stop);
        }
        assert_eq!((seen_a, seen_b), (2, 2));
    }

    #[test]
    fn silent_never_stops() {
        let mut silent = Silent;
        assert!(!Observer::<Count>::observe(&mut silent, &Count { done: 1, total: 1 }).is_stop());
        assert_eq!(Flow::default(), Flow::Continue);
    }
}
