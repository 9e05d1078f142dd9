//! Shared inputs for rappel's criterion benchmarks (see `benches/benches/`). The benchmarks live in
//! their own crate so that peers used only for comparison (spade, polyanya) stay dev-only.
