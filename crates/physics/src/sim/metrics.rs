//! What a whole throw did, read off its [`Summary`]: the checks of `../shared/reference/whole_throw.md`
//! §5 (Hewitt et al. 2011: no steady planing well above the minimal speed; the record runs' quick tail
//! of tiny hops, "pitty-pat"; Tang et al. 2021: the curve). Pure functions of the contact list, so the
//! tests, the fidelity study and the app read a throw the same way.

use super::Summary;

/// A throw's shape: how far, how many skips, and how it ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThrowShape {
    /// Contact episodes counted as skips (the summary's `skips`).
    pub skips: usize,
    /// Horizontal distance from the launch to where the run ended (m).
    pub distance: f64,
    /// Horizontal distance covered during the last contact episode (m): a planing glide when large.
    pub final_contact_length: f64,
    /// `final_contact_length / distance` (0 when the stone never moved).
    pub final_share: f64,
    /// Duration of the last contact (s).
    pub final_duration: f64,
    /// Longest contact before the last one (s); 0 with fewer than two contacts.
    pub longest_earlier_contact: f64,
    /// Longest distance between successive touchdowns over the last quarter of the touchdowns (m);
    /// 0 with fewer than 8 contacts.
    pub tail_longest_hop: f64,
    /// Sideways position of the centre of mass (m) at the last touchdown, relative to the launch.
    pub lateral: f64,
}

/// Reads a throw's shape from its summary; `launch` is the launch position's (x, y).
pub fn throw_shape(s: &Summary, launch: [f64; 2]) -> ThrowShape {
    let from_launch = |x: f64, y: f64| ((x - launch[0]).powi(2) + (y - launch[1]).powi(2)).sqrt();
    let c = &s.contacts;
    let (final_contact_length, final_duration, lateral) = match c.last() {
        Some(last) => (
            (s.distance - from_launch(last.x, last.y)).max(0.0),
            last.t_end - last.t_start,
            last.y - launch[1],
        ),
        None => (0.0, 0.0, 0.0),
    };
    let longest_earlier_contact = c
        .iter()
        .rev()
        .skip(1)
        .map(|e| e.t_end - e.t_start)
        .fold(0.0, f64::max);
    let tail_longest_hop = tail_hops(s).iter().map(|h| h.hop).fold(0.0, f64::max);
    ThrowShape {
        skips: s.skips,
        distance: s.distance,
        final_contact_length,
        final_share: if s.distance > 0.0 {
            final_contact_length / s.distance
        } else {
            0.0
        },
        final_duration,
        longest_earlier_contact,
        tail_longest_hop,
        lateral,
    }
}

/// One hop of a throw's tail: from a touchdown to the next, split into the part the stone covers
/// in contact and the part in flight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TailHop {
    /// The contact the hop starts with, counted from 1 over every contact (grazes included).
    pub contact: usize,
    /// Speed (m/s), angle below the horizontal (°) and tilt (°) at that touchdown.
    pub speed_in: f64,
    /// Angle of the velocity below the horizontal at that touchdown (°).
    pub beta_in: f64,
    /// Tilt at that touchdown (°; leading edge up > 0, relative to the direction of travel).
    pub tilt_in: f64,
    /// The contact's duration (s).
    pub contact_s: f64,
    /// Exit angle above the horizontal (°).
    pub exit_angle: f64,
    /// Touchdown to touchdown (m).
    pub hop: f64,
    /// The flight's length (m): its duration times the exit's horizontal speed (the air changes
    /// that speed by well under 1 % over a tail hop).
    pub flight: f64,
    /// `hop − flight` (m): what the stone covers while in contact.
    pub in_contact: f64,
}

/// The hops over the last quarter of the touchdowns (the record runs' "pitty-pat" tail,
/// whole_throw.md §3); none with fewer than 8 contacts.
pub fn tail_hops(s: &Summary) -> Vec<TailHop> {
    let c = &s.contacts;
    if c.len() < 8 {
        return Vec::new();
    }
    let first = c.len() * 3 / 4;
    c[first..]
        .windows(2)
        .enumerate()
        .map(|(k, w)| {
            let (a, b) = (&w[0], &w[1]);
            let hop = ((b.x - a.x).powi(2) + (b.y - a.y).powi(2)).sqrt();
            let horizontal = |v: [f64; 3]| v[0].hypot(v[1]);
            let exit_h = horizontal(a.v_out);
            let flight = (b.t_start - a.t_end).max(0.0) * exit_h;
            TailHop {
                contact: first + k + 1,
                speed_in: horizontal(a.v_in).hypot(a.v_in[2]),
                beta_in: a.beta_in,
                tilt_in: a.attitude_in[0],
                contact_s: a.t_end - a.t_start,
                exit_angle: a.v_out[2].atan2(exit_h).to_degrees(),
                hop,
                flight,
                in_contact: hop - flight,
            }
        })
        .collect()
}

/// The "no hovercraft" rule of issue 11: a throw that skips at least twice ends with a contact that
/// covers at most `max_share` of its distance, and no earlier contact lasts longer than
/// `max_contact` seconds. `None` when it holds (or the throw skipped fewer than twice), else why not.
pub fn hovercraft(shape: &ThrowShape, max_share: f64, max_contact: f64) -> Option<String> {
    if shape.skips < 2 {
        return None;
    }
    if shape.final_share > max_share {
        return Some(format!(
            "the last contact covers {:.0} % of the distance ({:.2} m of {:.2} m)",
            100.0 * shape.final_share,
            shape.final_contact_length,
            shape.distance
        ));
    }
    if shape.longest_earlier_contact > max_contact {
        return Some(format!(
            "an earlier contact lasts {:.3} s",
            shape.longest_earlier_contact
        ));
    }
    None
}

/// Least-squares slope of ln y over ln x (the exponent p of y ∝ x^p, e.g. skips against spin);
/// `None` below two positive points.
pub fn fit_exponent(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::ContactEvent;

    fn contact(t0: f64, t1: f64, x: f64) -> ContactEvent {
        ContactEvent {
            t_start: t0,
            t_end: t1,
            skip: true,
            graze: false,
            x,
            y: 0.0,
            v_in: [0.0; 3],
            v_out: [0.0; 3],
            attitude_in: [0.0; 3],
            attitude_out: [0.0; 3],
            beta_in: 0.0,
            peak_lift: 0.0,
            touches: 1,
            weight: 1.0,
            exit_xy: [x, 0.0],
            open: false,
        }
    }

    fn summary(contacts: Vec<ContactEvent>, distance: f64) -> Summary {
        Summary {
            schema: 1,
            name: String::new(),
            outcome: None,
            skips: contacts.len().saturating_sub(1),
            distance,
            final_time: 0.0,
            steps: 0,
            force_evals: 0,
            contacts,
            water: None,
            diverged_reason: None,
        }
    }

    #[test]
    fn a_long_last_contact_is_a_glide() {
        let s = summary(
            vec![
                contact(0.1, 0.12, 1.0),
                contact(0.3, 0.32, 3.0),
                contact(0.5, 3.0, 5.0),
            ],
            20.0,
        );
        let t = throw_shape(&s, [0.0, 0.0]);
        assert!((t.final_contact_length - 15.0).abs() < 1e-12);
        assert!((t.final_share - 0.75).abs() < 1e-12);
        assert!((t.longest_earlier_contact - 0.02).abs() < 1e-12);
        assert!(hovercraft(&t, 0.1, 0.3).is_some());
    }

    #[test]
    fn tail_hops_are_measured_over_the_last_quarter() {
        let xs = [1.0, 3.0, 4.5, 5.5, 6.2, 6.6, 6.9, 7.1];
        let s = summary(
            xs.iter()
                .enumerate()
                .map(|(i, &x)| contact(i as f64, i as f64 + 0.01, x))
                .collect(),
            7.2,
        );
        let t = throw_shape(&s, [0.0, 0.0]);
        assert!(
            (t.tail_longest_hop - 0.2).abs() < 1e-12,
            "{}",
            t.tail_longest_hop
        );
        assert!(hovercraft(&t, 0.1, 0.3).is_none());
    }

    #[test]
    fn a_tail_hop_is_its_contacts_slide_plus_its_flight() {
        // Eight contacts, 50 ms each at 4 m/s, leaving at 3 m/s forward and 0.3 m/s up; each
        // flight lasts 0.1 s (0.3 m), each slide 0.2 m: touchdowns 0.5 m apart.
        let contacts = (0..8)
            .map(|i| {
                let t0 = 0.15 * i as f64;
                let mut e = contact(t0, t0 + 0.05, 0.5 * i as f64);
                e.v_in = [4.0, 0.0, -0.3];
                e.v_out = [3.0, 0.0, 0.3];
                e.beta_in = 4.3;
                e.attitude_in = [6.0, 0.0, 0.0];
                e
            })
            .collect();
        let s = summary(contacts, 3.6);
        let hops = tail_hops(&s);
        // The last quarter is contacts 7 and 8: one hop, from contact 7.
        assert_eq!(hops.len(), 1);
        let h = hops[0];
        assert_eq!(h.contact, 7);
        assert!((h.hop - 0.5).abs() < 1e-12);
        assert!((h.flight - 0.3).abs() < 1e-12, "{}", h.flight);
        assert!((h.in_contact - 0.2).abs() < 1e-12);
        assert!((h.contact_s - 0.05).abs() < 1e-12);
        assert!((h.speed_in - 4.0f64.hypot(0.3)).abs() < 1e-12);
        assert!((h.exit_angle - 0.1f64.atan().to_degrees()).abs() < 1e-9);
        assert_eq!((h.beta_in, h.tilt_in), (4.3, 6.0));
        assert!(tail_hops(&summary(Vec::new(), 0.0)).is_empty());
    }
}
