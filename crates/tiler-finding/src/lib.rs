//! tiler-finding: advice about a frame, as plain data. An advisor (tiler-gl's, of GL traces and
//! render passes) produces [`Finding`]s; a report (tiler-report's JSON, HTML and text) shows
//! them. Each names the rule behind it, where in the frame it happened and what it cost in this
//! frame.
//!
//! Its own crate because both sides need it and neither depends on the other: tiler-gl (the
//! driver and its advisor) and tiler-report (the report writer) each depend only on the core,
//! and the command-line tool joins them.
//!
//! The JSON form is the `findings[]` of the `tiler-report/1` schema (`docs/report-schema.md`):
//! fields may be added, never removed. Fields added since the schema's first version are
//! written only when set, so a finding that does not use them serializes as it always did.

use serde::{Deserialize, Serialize};

/// How much a finding matters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Severity {
    /// Worth knowing; may be intended; costs nothing by itself.
    Info,
    /// Costs bandwidth, shading work or latency that could be saved.
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
    /// The rule, in a sentence; empty when not given.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub text: String,
}

/// A command numbered by its frame and its position in the frame (as GL traces number calls).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CallAt {
    /// Frame number, from 0.
    pub frame: u64,
    /// The command's index within its frame, from 0.
    pub call: u64,
    /// The number of the captured call it came from, when the frame is a replayed capture
    /// (apitrace numbers a capture's calls from 0, as `apitrace dump` prints them).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub capture_call: Option<u64>,
}

/// Where a finding happened; any part may be unknown.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Location {
    /// Frame number, from 0.
    pub frame: Option<u64>,
    /// Render pass, from 0: within the frame, or across the run for a GL trace's passes.
    pub pass: Option<u64>,
    /// The command at fault, e.g. `glClear #12` or `call 5`.
    pub call: Option<String>,
    /// The same command by number, when the commands are numbered (GL traces).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub call_at: Option<CallAt>,
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
    /// A stable identifier of the kind of finding, e.g. `load-at-pass-start`.
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
    /// Frames of CPU–GPU pipelining lost, when it stalls.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cost_stall_frames: Option<u64>,
    /// What happened.
    pub message: String,
    /// What to change.
    pub advice: String,
    /// What it costs on each device of a report that replayed the frame on several (the
    /// `cost_*` fields above are the first such device's); a device on which it costs
    /// nothing is not listed. Empty for a report of one device.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub costs: Vec<DeviceCost>,
    /// The fix tried (`tiler analyze --what-if`): applied to the frame and replayed on each
    /// device, or why it could not be.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub what_if: Vec<WhatIf>,
}

/// A finding's fix applied to the frame and the frame replayed on one device.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WhatIf {
    /// The device's label in the report.
    pub device: String,
    /// The edit made to the frame, or why there is none.
    pub fix: String,
    /// Whether the fix was applied and the frame replayed.
    pub applied: bool,
    /// External-memory bytes the replay with the fix moved fewer than the frame as it was
    /// (negative: more); `null` when not applied.
    pub measured_bytes: Option<i64>,
    /// The finding's estimate on this device, bytes.
    pub estimated_bytes: Option<u64>,
    /// Fragments the replay with the fix shaded fewer (negative: more); `null` when not
    /// applied.
    #[serde(default)]
    pub measured_fragments: Option<i64>,
    /// The finding's estimate on this device, fragments.
    #[serde(default)]
    pub estimated_fragments: Option<u64>,
    /// Whether the replay presented the same pictures, bit for bit: every presented frame
    /// and the window at the end.
    pub same_picture: Option<bool>,
    /// When the pictures differ: the first frame (from 0) whose presented picture differs
    /// (the run's frame count when only the window at the end does).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub different_frame: Option<u64>,
    /// Bytes the replay with the fix moved fewer, counting the tile stores transaction
    /// elimination skipped as moved (`measured_bytes` + the change in
    /// `transaction_elimination_saved_bytes`): what the fix saves whatever the pictures, the
    /// figure the estimate prices. Equal to `measured_bytes` on a device without transaction
    /// elimination; written only when it differs from it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured_bytes_before_elimination: Option<i64>,
}

/// What a finding costs on one device.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DeviceCost {
    /// The device's label in the report (its column).
    pub device: String,
    #[serde(default)]
    pub cost_bytes: Option<u64>,
    #[serde(default)]
    pub cost_fragments: Option<u64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cost_stall_frames: Option<u64>,
}

impl Finding {
    /// The same finding: the same rule at the same place about the same thing — its message
    /// equal but for its figures, which differ from device to device (two findings at one
    /// place, e.g. the depth and the stencil stored unread, stay two).
    pub fn same_as(&self, other: &Finding) -> bool {
        let words = |text: &str| text.chars().filter(|c| !c.is_ascii_digit() && *c != '.').collect::<String>();
        self.id == other.id && self.location == other.location && words(&self.message) == words(&other.message)
    }

    /// What it costs, as the device `device` prices it.
    pub fn cost_on(&self, device: &str) -> DeviceCost {
        DeviceCost {
            device: device.to_string(),
            cost_bytes: self.cost_bytes,
            cost_fragments: self.cost_fragments,
            cost_stall_frames: self.cost_stall_frames,
        }
    }
}

/// The findings of one frame replayed on several devices, one list per device (labelled):
/// each finding once, in the order of first appearance, with what it costs on each device
/// that reports it. A finding a device does not report costs nothing there.
pub fn merge_per_device(per_device: &[(String, Vec<Finding>)]) -> Vec<Finding> {
    let mut merged: Vec<Finding> = Vec::new();
    for (device, findings) in per_device {
        for finding in findings {
            match merged.iter_mut().find(|m| m.same_as(finding)) {
                Some(m) => {
                    m.costs.push(finding.cost_on(device));
                    m.what_if.extend(finding.what_if.iter().cloned());
                }
                None => {
                    let mut first = finding.clone();
                    first.costs = vec![finding.cost_on(device)];
                    merged.push(first);
                }
            }
        }
    }
    merged
}

#[cfg(test)]
mod tests {
    use super::*;

    fn finding() -> Finding {
        Finding {
            id: "load-at-pass-start".into(),
            severity: Severity::Warning,
            rule: Rule { seed: "001".into(), section: "render passes".into(), text: String::new() },
            location: Location { frame: Some(0), pass: Some(1), call: Some("glClear #12".into()), call_at: None },
            cost_bytes: Some(4096),
            cost_fragments: None,
            cost_stall_frames: None,
            message: "loads".into(),
            advice: "clear".into(),
            costs: Vec::new(),
            what_if: Vec::new(),
        }
    }

    /// A finding that sets none of the added fields serializes as `tiler-report/1` first
    /// wrote it: exactly these fields.
    #[test]
    fn added_fields_are_written_only_when_set() {
        let json = serde_json::to_value(finding()).unwrap();
        let keys = |v: &serde_json::Value| {
            let mut keys: Vec<String> = v.as_object().unwrap().keys().cloned().collect();
            keys.sort();
            keys
        };
        assert_eq!(
            keys(&json),
            ["advice", "cost_bytes", "cost_fragments", "id", "location", "message", "rule", "severity"]
        );
        assert_eq!(keys(&json["rule"]), ["section", "seed"]);
        assert_eq!(keys(&json["location"]), ["call", "frame", "pass"]);

        let mut full = finding();
        full.rule.text = "clear at the start".into();
        full.location.call_at = Some(CallAt { frame: 0, call: 12, capture_call: Some(5780) });
        full.cost_stall_frames = Some(2);
        let json = serde_json::to_value(&full).unwrap();
        assert_eq!(json["rule"]["text"], "clear at the start");
        assert_eq!(json["location"]["call_at"]["call"], 12);
        assert_eq!(json["cost_stall_frames"], 2);
        assert_eq!(serde_json::from_value::<Finding>(json).unwrap(), full);
    }

    #[test]
    fn findings_of_several_devices_merge_with_each_devices_cost() {
        let mut cheaper = finding();
        cheaper.cost_bytes = Some(1024);
        let mut other = finding();
        other.message = "stencil loads".into();
        let merged = merge_per_device(&[
            ("tbr".into(), vec![finding(), other.clone()]),
            ("tbdr".into(), vec![cheaper]),
            ("imr".into(), Vec::new()),
        ]);
        assert_eq!(merged.len(), 2);
        let devices: Vec<(&str, Option<u64>)> =
            merged[0].costs.iter().map(|c| (c.device.as_str(), c.cost_bytes)).collect();
        assert_eq!(devices, [("tbr", Some(4096)), ("tbdr", Some(1024))]);
        assert_eq!(merged[1].costs.len(), 1);
        let json = serde_json::to_value(&merged[0]).unwrap();
        assert_eq!(json["costs"][1]["device"], "tbdr");
        assert_eq!(serde_json::from_value::<Finding>(json).unwrap(), merged[0]);
    }

    #[test]
    fn a_location_describes_what_it_knows() {
        assert_eq!(finding().location.describe(), "frame 0, pass 1, glClear #12");
        assert_eq!(Location::default().describe(), "");
    }
}
