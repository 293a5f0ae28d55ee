//! Reports of a run: the readable summary, the JSON object and the trajectory CSV of
//! `stoneskip simulate` (design.md §7, contract).

use std::io::Write;

use glam::DVec3;

use stoneskip_physics::sim::air::Air;
use stoneskip_physics::sim::integrate::{fly, BodyState};
use stoneskip_physics::sim::params::Rotation;
use stoneskip_physics::sim::stone::Stone;
use stoneskip_physics::sim::{ending, Ending, Simulation, StepSample, Summary};

/// The CSV header (design.md §7).
pub const CSV_HEADER: &str =
    "t,x,y,z,vx,vy,vz,qw,qx,qy,qz,wx,wy,wz,in_contact,wetted_area,fx,fy,fz";

/// Longest gap between two CSV rows in flight (s).
pub const CSV_FLIGHT_INTERVAL: f64 = 1.0 / 240.0;

/// Human-readable summary with a table of contacts.
pub fn text_summary(s: &Summary) -> String {
    let mut out = String::new();
    // In words, with the JSON's name where they differ ("left the lake (left_domain)").
    let outcome = s.outcome.map_or("running".to_owned(), |o| {
        if o.words() == o.as_str() {
            o.words().to_owned()
        } else {
            format!("{} ({})", o.words(), o.as_str())
        }
    });
    out.push_str(&format!("{}\n", s.name));
    out.push_str(&format!(
        "outcome {outcome}, {} skip{}, distance {:.3} m, time {:.4} s ({} steps, {} force evaluations)\n",
        s.skips,
        if s.skips == 1 { "" } else { "s" },
        s.distance,
        s.final_time,
        s.steps,
        s.force_evals
    ));
    if s.outcome.is_some() {
        out.push_str(&format!("ending: {}\n", ending(s).words()));
    }
    if let Some(reason) = &s.diverged_reason {
        out.push_str(&format!("diverged: {reason}\n"));
    }
    if let Some(w) = s.water.as_ref().filter(|w| !w.stepped) {
        out.push_str(&format!(
            "water left at rest ({:.6} m³): nothing in this run reads it (wavy contact off; --step-water steps it)\n",
            w.volume_initial,
        ));
    }
    if let Some(w) = s.water.as_ref().filter(|w| w.stepped) {
        let drift = if w.volume_initial > 0.0 {
            (w.volume_final - w.volume_initial) / w.volume_initial
        } else {
            0.0
        };
        out.push_str(&format!(
            "water volume {:.6} m³ -> {:.6} m³ (relative change {drift:.2e})\n",
            w.volume_initial, w.volume_final
        ));
    }
    if !s.contacts.is_empty() {
        out.push_str(
            "  #   t_start(s)  t_end(s)  dur(ms)   x(m)    y(m)  v_in(m/s) beta_in(°) tilt_in(°) v_out(m/s) lift(N) touches  skip\n",
        );
        for (i, c) in s.contacts.iter().enumerate() {
            let vin = DVec3::from_array(c.v_in).length();
            let vout = DVec3::from_array(c.v_out).length();
            out.push_str(&format!(
                "{:>3} {:>11.4} {:>9.4} {:>8.2} {:>7.3} {:>7.3} {:>9.3} {:>10.2} {:>10.2} {:>10.3} {:>7.2} {:>7}  {}\n",
                i + 1,
                c.t_start,
                c.t_end,
                1000.0 * (c.t_end - c.t_start),
                c.x,
                c.y,
                vin,
                c.beta_in,
                c.attitude_in[0],
                vout,
                c.peak_lift,
                c.touches,
                if c.skip {
                    "yes"
                } else if c.graze {
                    "graze"
                } else {
                    "no"
                }
            ));
        }
    }
    out
}

/// JSON object of a run (design.md §7), with why it ended (issue 48): `ending` (its `kind` and
/// the numbers that decided it) and `ending_words`, the words the app shows.
pub fn json_summary(s: &Summary) -> Result<String, serde_json::Error> {
    #[derive(serde::Serialize)]
    struct WithEnding<'a> {
        #[serde(flatten)]
        summary: &'a Summary,
        ending: Ending,
        ending_words: String,
    }
    let e = ending(s);
    serde_json::to_string_pretty(&WithEnding {
        summary: s,
        ending: e,
        ending_words: e.words(),
    })
}

/// Writes the trajectory CSV: a row per accepted step, and flight rows in between so that no gap
/// in flight exceeds [`CSV_FLIGHT_INTERVAL`].
pub struct CsvWriter<W: Write> {
    out: W,
    last: Option<StepSample>,
    stone: Stone,
    rotation: Rotation,
    gravity: f64,
    air: Option<Air>,
}

impl<W: Write> CsvWriter<W> {
    /// For the run `sim` (its stone and flight model fill the flight rows).
    pub fn new(mut out: W, sim: &Simulation) -> std::io::Result<Self> {
        writeln!(out, "{CSV_HEADER}")?;
        let physics = &sim.preset().physics;
        Ok(Self {
            out,
            last: None,
            stone: sim.stone().clone(),
            rotation: physics.rotation,
            gravity: physics.gravity,
            air: sim.air().copied(),
        })
    }

    /// Writes the first row (the launch state).
    pub fn start(&mut self, sample: &StepSample) -> std::io::Result<()> {
        self.row(sample)?;
        self.last = Some(*sample);
        Ok(())
    }

    pub fn step(&mut self, sample: &StepSample) -> std::io::Result<()> {
        if let Some(prev) = self.last {
            let gap = sample.time - prev.time;
            if !prev.in_contact && !sample.in_contact && gap > CSV_FLIGHT_INTERVAL {
                let n = (gap / CSV_FLIGHT_INTERVAL).ceil() as usize;
                for k in 1..n {
                    let t = gap * k as f64 / n as f64;
                    let st: BodyState = fly(
                        &self.stone,
                        self.rotation,
                        self.gravity,
                        self.air.as_ref(),
                        &prev.state,
                        t,
                    );
                    self.row(&StepSample {
                        time: prev.time + t,
                        state: st,
                        in_contact: false,
                        wetted_area: 0.0,
                        force: DVec3::ZERO,
                        ..prev
                    })?;
                }
            }
        }
        self.row(sample)?;
        self.last = Some(*sample);
        Ok(())
    }

    fn row(&mut self, s: &StepSample) -> std::io::Result<()> {
        let p = s.state.position;
        let v = s.state.velocity;
        let q = s.state.orientation;
        let w = s.angular_velocity;
        writeln!(
            self.out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            s.time,
            p.x,
            p.y,
            p.z,
            v.x,
            v.y,
            v.z,
            q.w,
            q.x,
            q.y,
            q.z,
            w.x,
            w.y,
            w.z,
            u8::from(s.in_contact),
            s.wetted_area,
            s.force.x,
            s.force.y,
            s.force.z
        )
    }

    pub fn finish(mut self) -> std::io::Result<W> {
        self.out.flush()?;
        Ok(self.out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use stoneskip_physics::sim::Outcome;

    fn diverged() -> Summary {
        Summary {
            schema: 1,
            name: "test".into(),
            outcome: Some(Outcome::Diverged),
            diverged_reason: Some("the Paper integrator's state became non-finite".into()),
            skips: 0,
            distance: 1.0,
            final_time: 0.5,
            steps: 10,
            force_evals: 10,
            contacts: Vec::new(),
            water: None,
        }
    }

    /// A diverged run says so, with its reason, in the text and in the JSON (design.md §7's fields
    /// kept, `diverged_reason` added).
    #[test]
    fn diverged_run_is_reported_with_its_reason() {
        let s = diverged();
        let text = text_summary(&s);
        assert!(text.contains("outcome diverged"), "{text}");
        assert!(text.contains("diverged: the Paper integrator"), "{text}");
        let v: serde_json::Value = serde_json::from_str(&json_summary(&s).unwrap()).unwrap();
        assert_eq!(v["outcome"], "diverged");
        assert_eq!(
            v["diverged_reason"],
            "the Paper integrator's state became non-finite"
        );
        for key in ["schema", "name", "skips", "distance", "final_time", "steps"] {
            assert!(v.get(key).is_some(), "{key}");
        }
        let mut ok = s;
        ok.outcome = Some(Outcome::Sank);
        ok.diverged_reason = None;
        let v: serde_json::Value = serde_json::from_str(&json_summary(&ok).unwrap()).unwrap();
        assert!(v["diverged_reason"].is_null());
        assert!(!text_summary(&ok).contains("diverged"));
    }

    /// The text says what happened in words, with the JSON's name beside it where they differ
    /// (issue 39: the CLI read `left_domain` where the app says "left the lake").
    #[test]
    fn the_text_outcome_is_in_words() {
        let mut s = diverged();
        s.diverged_reason = None;
        s.outcome = Some(Outcome::LeftDomain);
        let text = text_summary(&s);
        assert!(
            text.contains("outcome left the lake (left_domain),"),
            "{text}"
        );
        s.outcome = Some(Outcome::Sank);
        assert!(text_summary(&s).contains("outcome sank,"));
        s.outcome = Some(Outcome::Timeout);
        assert!(text_summary(&s).contains("still going at the time limit (timeout)"));
    }

    /// Issue 48: the text and the JSON say why the throw ended, from its last touch.
    #[test]
    fn the_ending_is_reported_from_the_last_touch() {
        let mut s = diverged();
        s.diverged_reason = None;
        s.outcome = Some(Outcome::Sank);
        s.contacts = vec![stoneskip_physics::sim::ContactEvent {
            t_start: 0.1,
            t_end: 0.2,
            skip: false,
            graze: false,
            x: 1.0,
            y: 0.0,
            v_in: [5.0, 0.0, -0.5],
            v_out: [1.0, 0.0, 0.0],
            attitude_in: [-1.1, 0.0, 0.0],
            attitude_out: [-3.0, 0.0, 0.0],
            beta_in: 5.7,
            peak_lift: 0.0,
            touches: 1,
            weight: 1.0,
            exit_xy: [1.0, 0.0],
            open: false,
        }];
        let text = text_summary(&s);
        assert!(
            text.contains("ending: dug in nose-down at touch 1 (tilt -3.0°)"),
            "{text}"
        );
        let v: serde_json::Value = serde_json::from_str(&json_summary(&s).unwrap()).unwrap();
        assert_eq!(v["ending"]["kind"], "nose_down");
        assert_eq!(v["ending"]["touch"], 1);
        assert_eq!(
            v["ending_words"],
            "dug in nose-down at touch 1 (tilt -3.0°)"
        );
        assert_eq!(v["outcome"], "sank");
    }
}
