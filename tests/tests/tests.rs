//! Integration tests of tessera: one binary, one module per concern.

mod adaptive;
mod analytic;
mod board;
mod builtin_images;
mod convergence;
mod cores;
mod culling;
mod docs;
mod dualcore;
mod extremes;
mod finite;
mod firmware;
mod frustum;
mod golden;
mod install;
mod interference;
mod nofpu;
mod overlay;
mod pico2;
mod qemu_example;
mod reference;
mod sparse;
mod tiles;
mod workspace;
