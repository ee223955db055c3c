//! The advisor (stub while the context is built).
use crate::context::ContextConfig;
use crate::report::FrameRecord;
use serde::Serialize;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Severity {
    Warning,
    Info,
}

#[derive(Clone, Debug, Serialize)]
pub struct Finding {
    pub id: &'static str,
    pub severity: Severity,
}

pub fn advise(_config: &ContextConfig, _frames: &[FrameRecord]) -> Vec<Finding> {
    Vec::new()
}
