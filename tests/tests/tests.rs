//! Integration tests of tessera: one binary, one module per concern.

mod analytic;
mod builtin_images;
mod convergence;
mod extremes;
mod frustum;
mod golden;
mod reference;
mod tiles;
