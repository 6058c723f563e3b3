//! `no_std`, allocation-free real-time controller for a bidirectional MR brake.
#![cfg_attr(not(any(test, feature = "std")), no_std)]
