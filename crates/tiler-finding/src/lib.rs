//! Advisor findings: plain data an advisor (of render passes, of GL traces) produces and a
//! report shows. Each names the rule behind it, where in the frame it happened and what it
//! cost in this frame.

use serde::{Deserialize, Serialize};

/// How much a finding matters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Severity {
    /// Worth knowing; may be intended.
    Info,
    /// Costs bandwidth or shading work that could be saved.
    Warning,
    /// Defeats the tiler: flushes, reloads, full-frame traffic that should not exist.
    Error,
}

impl Severity {
    pub const fn name(self) -> &'static str {
        match self {
            Severity::Info => "info",
            Severity::Warning => "warning",
            Severity::Error => "error",
        }
    }
}

/// The rule a finding applies: a seed document and its section.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rule {
    /// The seed document, e.g. `003` or its title.
    pub seed: String,
    /// The section, e.g. `23.3`.
    pub section: String,
}

/// Where a finding happened; any part may be unknown.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Location {
    /// Frame number, from 0.
    pub frame: Option<u64>,
    /// Render pass within the frame, from 0.
    pub pass: Option<u64>,
    /// The command at fault, e.g. `glClear #12` or `draw 3`.
    pub call: Option<String>,
}

impl Location {
    /// `frame 0, pass 1, glClear #12`; empty when nothing is known.
    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        if let Some(frame) = self.frame {
            parts.push(format!("frame {frame}"));
        }
        if let Some(pass) = self.pass {
            parts.push(format!("pass {pass}"));
        }
        if let Some(call) = &self.call {
            parts.push(call.clone());
        }
        parts.join(", ")
    }
}

/// One piece of advice about the frame.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Finding {
    /// A stable identifier of the kind of finding, e.g. `load-then-overwrite`.
    pub id: String,
    pub severity: Severity,
    pub rule: Rule,
    pub location: Location,
    /// External-memory bytes it costs in this frame, when it costs bytes.
    #[serde(default)]
    pub cost_bytes: Option<u64>,
    /// Fragments shaded in vain in this frame, when it costs shading.
    #[serde(default)]
    pub cost_fragments: Option<u64>,
    /// What happened.
    pub message: String,
    /// What to change.
    pub advice: String,
}
