//! Integration tests of the capture reader, in one binary (link time matters on 2 cores).

#[path = "apitrace/common.rs"]
mod common;
#[path = "apitrace/fuzz.rs"]
mod fuzz;
#[path = "apitrace/gles.rs"]
mod gles;
#[path = "apitrace/shared.rs"]
mod shared;
#[path = "apitrace/wire.rs"]
mod wire;
#[path = "apitrace/writer.rs"]
mod writer;
