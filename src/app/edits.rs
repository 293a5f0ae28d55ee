//! What the panels changed against the loaded preset: each differing value with the preset's, so
//! a live edit that persists into later throws is marked and can be reverted. The launch is
//! compared in the panel's own terms (speed, elevation, heading, degrees, rev/s); the stone, the
//! physics and the water field by field through their serde form (new options need no code here).

use serde::Serialize;
use serde_json::Value;

use stoneskip_physics::sim::params::Launch;

/// Relative difference below which two numbers count as equal (slider round trips through
/// degrees and rev/s change the last digits).
pub const REL_EQUAL: f64 = 1e-9;

/// One value that differs from the loaded preset.
#[derive(Debug, Clone, PartialEq)]
pub struct Difference {
    /// The field as the panel names it.
    pub field: String,
    pub now: String,
    pub preset: String,
}

fn same(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= REL_EQUAL * a.abs().max(b.abs()).max(1e-12)
}

fn number(v: f64, unit: &str) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if unit.is_empty() {
        s.to_owned()
    } else {
        format!("{s} {unit}")
    }
}

/// The launch's differences, in the panel's units.
pub fn launch_differences(preset: &Launch, now: &Launch) -> Vec<Difference> {
    let speed = |l: &Launch| glam::DVec3::from_array(l.velocity).length();
    let elevation = |l: &Launch| {
        let s = speed(l);
        if s > 1e-12 {
            (l.velocity[2] / s).clamp(-1.0, 1.0).asin().to_degrees()
        } else {
            0.0
        }
    };
    let heading = |l: &Launch| l.velocity[1].atan2(l.velocity[0]).to_degrees();
    let tau = std::f64::consts::TAU;
    let pair = |f: &dyn Fn(&Launch) -> f64| (f(preset), f(now));
    let fields = [
        ("Speed", "m/s", pair(&speed)),
        ("Elevation", "°", pair(&elevation)),
        ("Heading", "°", pair(&heading)),
        ("Tilt", "°", pair(&|l| l.attitude.tilt_deg)),
        ("Bank", "°", pair(&|l| l.attitude.bank_deg)),
        ("Turn", "°", pair(&|l| l.attitude.heading_deg)),
        ("Spin", "rev/s", pair(&|l| l.spin / tau)),
        ("Position x", "m", pair(&|l| l.position[0])),
        ("Position y", "m", pair(&|l| l.position[1])),
        ("Position z", "m", pair(&|l| l.position[2])),
        ("Wobble x", "rad/s", pair(&|l| l.angular_velocity[0])),
        ("Wobble y", "rad/s", pair(&|l| l.angular_velocity[1])),
        ("Wobble z", "rad/s", pair(&|l| l.angular_velocity[2])),
    ];
    let mut out = Vec::new();
    for (field, unit, (a, b)) in fields {
        // Angles compare to a millionth of a degree (they come from velocities).
        let equal = if unit == "°" {
            (a - b).abs() < 1e-6
        } else {
            same(a, b)
        };
        if !equal {
            out.push(Difference {
                field: field.to_owned(),
                now: number(b, unit),
                preset: number(a, unit),
            });
        }
    }
    out
}

/// The differences of any serialisable section (stone, physics, water), field by field; a field
/// whose kind changed (another shape, a swell added) is one difference.
pub fn section_differences<T: Serialize>(preset: &T, now: &T) -> Vec<Difference> {
    let (Ok(a), Ok(b)) = (serde_json::to_value(preset), serde_json::to_value(now)) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    diff_values("", &a, &b, &mut out);
    out
}

fn shown(v: &Value) -> String {
    match v {
        Value::Number(n) => n.as_f64().map_or_else(|| n.to_string(), |x| number(x, "")),
        Value::String(s) => s.clone(),
        Value::Null => "none".to_owned(),
        other => other.to_string(),
    }
}

/// Two objects of the same kind: not two different enum variants (serde writes a variant as a
/// one-key object named after it).
fn same_kind(x: &serde_json::Map<String, Value>, y: &serde_json::Map<String, Value>) -> bool {
    let variant = |m: &serde_json::Map<String, Value>| {
        m.len() == 1
            && m.keys()
                .all(|k| k.starts_with(|c: char| c.is_ascii_uppercase()))
    };
    !(variant(x) || variant(y)) || x.keys().eq(y.keys())
}

fn diff_values(path: &str, a: &Value, b: &Value, out: &mut Vec<Difference>) {
    let join = |k: &str| {
        if path.is_empty() {
            k.to_owned()
        } else {
            format!("{path}.{k}")
        }
    };
    match (a, b) {
        // Same kind (both objects, no enum variant tag changed): field by field, a field the one
        // side leaves out (an optional one unset) counting as null.
        (Value::Object(x), Value::Object(y)) if same_kind(x, y) => {
            let mut keys: Vec<&String> = x.keys().chain(y.keys()).collect();
            keys.sort();
            keys.dedup();
            for k in keys {
                let (va, vb) = (x.get(k), y.get(k));
                diff_values(
                    &join(k),
                    va.unwrap_or(&Value::Null),
                    vb.unwrap_or(&Value::Null),
                    out,
                );
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => {
            for (i, (va, vb)) in x.iter().zip(y).enumerate() {
                diff_values(&format!("{path}[{i}]"), va, vb, out);
            }
        }
        (Value::Number(x), Value::Number(y)) => {
            let (Some(x), Some(y)) = (x.as_f64(), y.as_f64()) else {
                return;
            };
            if !same(x, y) {
                out.push(Difference {
                    field: path.replace('_', " "),
                    now: number(y, ""),
                    preset: number(x, ""),
                });
            }
        }
        _ if a != b => out.push(Difference {
            field: path.replace('_', " "),
            now: shown(b),
            preset: shown(a),
        }),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use stoneskip_physics::sim::params::{Preset, Shape};

    #[test]
    fn an_untouched_preset_differs_nowhere() {
        let p = Preset::version_1();
        assert!(launch_differences(&p.launch, &p.launch).is_empty());
        assert!(section_differences(&p.stone, &p.stone).is_empty());
        assert!(section_differences(&p.physics, &p.physics).is_empty());
        assert!(section_differences(&p.water, &p.water).is_empty());
    }

    #[test]
    fn a_faster_throw_is_one_difference_with_the_presets_value() {
        let p = Preset::version_1();
        let mut l = p.launch;
        let v = glam::DVec3::from_array(l.velocity);
        l.velocity = (v * 14.0 / v.length()).to_array();
        let d = launch_differences(&p.launch, &l);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].field, "Speed");
        assert_eq!(d[0].now, "14 m/s");
        assert_eq!(d[0].preset, number(v.length(), "m/s"));
        // Turning the throw changes the heading, not the speed.
        let mut t = p.launch;
        t.velocity = [v.x * 0.5, v.x * 0.75f64.sqrt(), v.z];
        let d = launch_differences(&p.launch, &t);
        assert!(
            d.iter().any(|d| d.field == "Heading" && d.now == "60 °"),
            "{d:?}"
        );
        assert!(d.iter().all(|d| d.field != "Speed"), "{d:?}");
        // A round trip through rev/s is no change.
        let mut s = p.launch;
        s.spin = (s.spin / std::f64::consts::TAU) * std::f64::consts::TAU;
        assert!(launch_differences(&p.launch, &s).is_empty());
    }

    #[test]
    fn sections_name_each_changed_field() {
        let p = Preset::version_1();
        let mut physics = p.physics;
        physics.gravity = 1.62;
        physics.dt *= 0.5;
        let d = section_differences(&p.physics, &physics);
        assert_eq!(d.len(), 2, "{d:?}");
        assert!(d.iter().any(|d| d.field == "gravity" && d.now == "1.62"));
        let mut water = p.water;
        water.size[0] += 5.0;
        let d = section_differences(&p.water, &water);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].field, "size[0]");
        // Another shape is one difference, not one per field.
        let mut stone = p.stone.clone();
        stone.shape = Shape::Disk {
            radius: 0.05,
            thickness: 0.01,
        };
        let d = section_differences(&p.stone, &stone);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].field, "shape");
        // An optional value set where the preset leaves it out is one difference, by its name.
        let mut physics = p.physics;
        physics.lift_coefficient = Some(1.0);
        let d = section_differences(&p.physics, &physics);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(
            (d[0].field.as_str(), d[0].preset.as_str(), d[0].now.as_str()),
            ("lift coefficient", "none", "1")
        );
    }
}
