//! The options a sensor sequence was made with, recorded in its folder as `options.json`
//! (issue 37, item 14): `dataset --sense` keeps a complete sequence only when it was made with
//! the options this run asks for, and otherwise refuses, naming the options that differ, as it
//! does for a world made with other options. Without the record, a run with another LiDAR kept
//! the old sequences and said it had kept them.
//!
//! What is recorded is the request as the user gave it (the world, the output folder, `--force`
//! and `--max-disk` left out: they do not change a sequence's bytes), with the formats in their
//! one canonical form, so `--format bag,kitti` and no `--format` are the same sequence.

use serde_json::{Value, json};
use subtgraph_sensors::SenseRequest;
use subtgraph_sensors::write::Formats;

/// The file in a sequence folder.
pub const FILE: &str = "options.json";

/// The record of `r`'s options (formats that do not parse are kept as given: the request is
/// refused for them before anything is written).
pub fn record(r: &SenseRequest) -> Value {
    let formats = match Formats::parse(&r.formats) {
        Ok(f) => json!({"bag": f.bag, "kitti": f.kitti}),
        Err(_) => json!(r.formats),
    };
    json!({
        "format": "subtgraph-sense-options/1",
        "platform": r.platform,
        "route": r.route,
        "lidar": r.lidar,
        "lidar_rate_hz": r.lidar_rate,
        "max_range_m": r.max_range,
        "imu_rate_hz": r.imu_rate,
        "imu_time_offset_s": r.imu_time_offset,
        "formats": formats,
        "wheel_odometry": r.wheel_odometry,
        "noiseless": r.noiseless,
        "duration_s": r.duration,
        "seed": r.seed,
    })
}

/// `options.json`'s text for `r`.
pub fn text(r: &SenseRequest) -> String {
    serde_json::to_string_pretty(&record(r)).expect("plain data") + "\n"
}

/// The options whose recorded value differs from `wanted`'s, as `name: RECORDED (this run:
/// WANTED)`, in name order.
pub fn differences(recorded: &Value, wanted: &Value) -> Vec<String> {
    let (Some(a), Some(b)) = (recorded.as_object(), wanted.as_object()) else {
        return vec!["the whole record (not a JSON object)".to_owned()];
    };
    let show = |v: Option<&Value>| match v {
        None | Some(Value::Null) => "not given".to_owned(),
        Some(Value::String(s)) => s.clone(),
        Some(v) => v.to_string(),
    };
    b.keys()
        .chain(a.keys().filter(|k| !b.contains_key(*k)))
        .filter(|k| a.get(*k) != b.get(*k))
        .map(|k| format!("{k}: {} (this run: {})", show(a.get(k)), show(b.get(k))))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_options_however_written_have_one_record_and_others_are_named() {
        let a = SenseRequest {
            formats: vec!["bag,kitti".into()],
            ..SenseRequest::default()
        };
        let b = SenseRequest {
            world: "elsewhere".into(),
            force: true,
            max_disk: Some(1 << 30),
            ..SenseRequest::default()
        };
        assert_eq!(record(&a), record(&b));
        assert!(differences(&record(&a), &record(&b)).is_empty());
        let c = SenseRequest {
            lidar: "vlp-16".into(),
            duration: Some(3.0),
            ..SenseRequest::default()
        };
        assert_eq!(
            differences(&record(&a), &record(&c)),
            [
                "duration_s: not given (this run: 3.0)",
                "lidar: os1-32 (this run: vlp-16)"
            ]
        );
    }
}
