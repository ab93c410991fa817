//! Integration tests of tessera: one binary, one module per concern.

mod adaptive;
mod analytic;
mod builtin_images;
mod changes;
mod convergence;
mod cores;
mod culling;
mod docs;
mod dualcore;
/// The examples users copy (`examples/`), each built as its README says. Their
/// module sorts before the firmware and reference tests, so that the longest
/// chain of builds (the qemu example's scenes, one after the other in its one
/// target folder) starts early and the other test thread has work beside it.
mod examples {
    mod board;
    mod pico2;
    mod qemu;
}
mod extremes;
mod finite;
mod firmware;
mod frustum;
mod golden;
mod install;
mod interference;
mod moving;
mod nofpu;
mod overlay;
mod reference;
mod sparse;
mod tiles;
mod workspace;
