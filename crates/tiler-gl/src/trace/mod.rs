//! Traces (stub).
