//! ROS `map_server` YAML reader (no image is read): never panics; errors and warnings
//! name lines inside the text (counted with YAML's line breaks); a file it reads has
//! finite numbers.
#![no_main]

use libfuzzer_sys::fuzz_target;
use planner_maps::parse_ros_yaml;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    // YAML's line breaks: \n, \r\n and a lone \r.
    let n_lines = text.replace("\r\n", "\n").split(['\n', '\r']).count();
    match parse_ros_yaml(text, "fuzz.yaml") {
        Ok(yaml) => {
            assert!(!yaml.image.is_empty());
            assert!(yaml.resolution.is_finite());
            assert!(yaml.origin.iter().all(|v| v.is_finite()));
            for warning in &yaml.warnings {
                assert!(warning.line <= n_lines, "{warning} ({n_lines} lines)");
                let _ = warning.to_string();
            }
        }
        Err(err) => {
            assert!(err.line <= n_lines, "{err} ({n_lines} lines)");
            let _ = err.to_string();
        }
    }
});
