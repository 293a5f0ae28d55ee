//! The attitude study's outputs: CSV tables, a chart of skips against spin, and the Markdown
//! report with each finding named physics (with its source) or fixed (with its test).

use super::{
    AirRow, Landing, OneContact, Results, Throw, Variant, ZigRow, CLANET_ANGLE_DEG, CLANET_SPEED,
    CP_SLENDER_CIRCLE, CP_THIN_AEROFOIL,
};
use crate::study::plot::{self, Chart, Legend, Mark, Panel, RefLine, Series};
use crate::study::style::colors;
use crate::study::table::{md_table, sig, Csv};
use crate::study::{Ctx, StudyError};

pub fn write(ctx: &Ctx, r: &Results) -> Result<(), StudyError> {
    write_csvs(ctx, r)?;
    spin_figure(ctx, r)?;
    ctx.write("README.md", &report(ctx, r))
}

fn f1(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.1}")
    } else {
        "n/a".into()
    }
}

fn write_csvs(ctx: &Ctx, r: &Results) -> Result<(), StudyError> {
    air_csv(ctx, r)?;
    clanet_csv(ctx, r)?;
    spin_csvs(ctx, r)?;
    landings_csv(ctx, r)?;
    mass_csv(ctx, r)
}

/// The flight to the first touch under each air variant.
fn air_csv(ctx: &Ctx, r: &Results) -> Result<(), StudyError> {
    let mut air = Csv::new(&[
        "speed_m_s",
        "variant",
        "moment_slope_per_rad",
        "flight_s",
        "axis_turn_deg",
        "momentum_turn_deg",
        "gyro_turn_deg",
        "launch_estimate_deg",
        "tilt_at_touch_deg",
        "bank_at_touch_deg",
        "skips",
        "distance_m",
    ]);
    for a in &r.air {
        air.push(vec![
            a.speed.into(),
            a.variant.key().into(),
            a.moment_slope.into(),
            a.flight.time.into(),
            a.flight.axis_turn.into(),
            a.flight.momentum_turn.into(),
            a.flight.gyro_turn.into(),
            a.flight.launch_estimate.into(),
            a.flight.tilt.into(),
            a.flight.bank.into(),
            a.throw.skips.into(),
            a.throw.distance.into(),
        ]);
    }
    ctx.write_csv("air_moment.csv", &air)
}

/// Clanet's disc through one contact, over spin.
fn clanet_csv(ctx: &Ctx, r: &Results) -> Result<(), StudyError> {
    let mut cl = Csv::new(&[
        "spin_rev_s",
        "duration_s",
        "skip",
        "tilt_in_deg",
        "tilt_out_deg",
        "bank_in_deg",
        "bank_out_deg",
        "axis_turn_deg",
        "gyro_turn_deg",
        "momentum_turn_deg",
        "momentum_kg_m2_s",
        "moment_impulse_n_m_s",
        "impulse_n_s",
        "lever_m",
        "nutation_deg",
    ]);
    for c in &r.clanet {
        cl.push(vec![
            c.rev_s.into(),
            c.duration.into(),
            c.skip.into(),
            c.tilt_in.into(),
            c.tilt_out.into(),
            c.bank_in.into(),
            c.bank_out.into(),
            c.axis_turn.into(),
            c.gyro_turn.into(),
            c.momentum_turn.into(),
            c.momentum.into(),
            c.moment_impulse.into(),
            c.impulse.into(),
            c.lever.into(),
            c.nutation.into(),
        ]);
    }
    ctx.write_csv("clanet_contact.csv", &cl)
}

/// The default's skips and mean tilt against spin, and the held count against tilt.
fn spin_csvs(ctx: &Ctx, r: &Results) -> Result<(), StudyError> {
    let mut sp = Csv::new(&[
        "spin_rev_s",
        "skips_free",
        "mean_tilt_deg",
        "mean_bank_deg",
        "skips_held_at_mean_tilt",
        "energy_weighted_tilt_deg",
        "skips_held_at_energy_weighted_tilt",
        "skips_held_at_launch_tilt",
    ]);
    for s in &r.spin {
        sp.push(vec![
            s.rev_s.into(),
            s.free.skips.into(),
            s.mean_tilt.into(),
            s.mean_bank.into(),
            s.held_at_mean.into(),
            s.energy_tilt.into(),
            s.held_at_energy.into(),
            r.held_launch.into(),
        ]);
    }
    ctx.write_csv("spin_tilt.csv", &sp)?;

    let mut ht = Csv::new(&["tilt_deg", "skips_held"]);
    for &(t, n) in &r.held_tilts {
        ht.push(vec![t.into(), n.into()]);
    }
    ctx.write_csv("held_tilt.csv", &ht)
}

/// Every landing of the zig-zag cases and of the spin sweep.
fn landings_csv(ctx: &Ctx, r: &Results) -> Result<(), StudyError> {
    let mut land = Csv::new(&[
        "case",
        "value",
        "variant",
        "contact",
        "x_m",
        "speed_m_s",
        "beta_deg",
        "tilt_in_deg",
        "bank_in_deg",
        "tilt_out_deg",
        "bank_out_deg",
        "skip",
    ]);
    for z in &r.zig {
        for (variant, t) in [
            (Variant::Shipped, &z.shipped),
            (Variant::NoMoment, &z.no_moment),
            (Variant::Held, &z.held),
        ] {
            push_landings(&mut land, z.case, z.value, variant, &t.landings);
        }
    }
    for x in &r.spin {
        push_landings(
            &mut land,
            "spin",
            x.rev_s,
            Variant::Shipped,
            &x.free.landings,
        );
    }
    ctx.write_csv("landings.csv", &land)
}

/// The finer mass sweep, when it ran.
fn mass_csv(ctx: &Ctx, r: &Results) -> Result<(), StudyError> {
    if r.mass_sweep.is_empty() {
        return Ok(());
    }
    let mut ms = Csv::new(&[
        "mass_kg",
        "skips",
        "second_landing_tilt_deg",
        "second_landing_bank_deg",
    ]);
    for &(m, n, t, b) in &r.mass_sweep {
        ms.push(vec![m.into(), n.into(), t.into(), b.into()]);
    }
    ctx.write_csv("mass_sweep.csv", &ms)?;
    Ok(())
}

/// One row per landing of `landings`, numbered from 1.
fn push_landings(csv: &mut Csv, case: &str, value: f64, variant: Variant, landings: &[Landing]) {
    for (i, l) in landings.iter().enumerate() {
        csv.push(vec![
            case.into(),
            value.into(),
            variant.key().into(),
            (i + 1).into(),
            l.x.into(),
            l.speed.into(),
            l.beta.into(),
            l.tilt.into(),
            l.bank.into(),
            l.tilt_out.into(),
            l.bank_out.into(),
            l.skip.into(),
        ]);
    }
}

/// spin.png: skips against spin, free and held at the mean tilt, with the mean tilt.
fn spin_figure(ctx: &Ctx, r: &Results) -> Result<(), StudyError> {
    let x = |s: f64| s.max(1.0);
    let free: Vec<(f64, f64)> = r
        .spin
        .iter()
        .map(|s| (x(s.rev_s), s.free.skips as f64))
        .collect();
    let held: Vec<(f64, f64)> = r
        .spin
        .iter()
        .map(|s| (x(s.rev_s), s.held_at_mean as f64))
        .collect();
    let tilt: Vec<(f64, f64)> = r.spin.iter().map(|s| (x(s.rev_s), s.mean_tilt)).collect();
    let chart = Chart::new(
        "default throw (12 m/s, 20°): skips and mean tilt at the contacts against spin",
        "spin (rev/s; 0 drawn at 1)",
        "skips / mean tilt (°)",
    )
    .log_x()
    .x_range(0.8, 200.0)
    .y_range(-1.0, 36.0)
    .legend(Legend::UpperRight)
    .series(Series::new(
        "skips, free",
        free,
        colors::BLUE,
        Mark::LinePoints,
    ))
    .series(Series::new(
        "skips, attitude held at the free stone's mean tilt",
        held,
        colors::RED,
        Mark::LinePoints,
    ))
    .series(Series::new(
        "mean tilt at the contacts (°)",
        tilt,
        colors::GREEN,
        Mark::Dashed,
    ))
    .line(RefLine::h(
        format!("held at the launch tilt: {}", r.held_launch),
        r.held_launch as f64,
        colors::GREY,
    ));
    plot::draw(
        &ctx.path("spin.png"),
        (1100, 700),
        1,
        None,
        &[Panel::Chart(chart)],
    )
}

fn landings_cell(t: &Throw, n: usize) -> String {
    let mut parts: Vec<String> = t
        .landings
        .iter()
        .take(n)
        .map(|l| format!("{:.0}/{:.0}", l.tilt, l.bank))
        .collect();
    if t.landings.len() > n {
        parts.push("…".into());
    }
    parts.join(", ")
}

fn air_table(rows: &[AirRow]) -> String {
    let body: Vec<Vec<String>> = rows
        .iter()
        .map(|a| {
            vec![
                format!("{}", a.speed),
                match a.variant {
                    Variant::NoAir => "no air".into(),
                    _ => format!("C_Mα {:.2}", a.moment_slope),
                },
                format!("{:.3}", a.flight.time),
                f1(a.flight.axis_turn),
                f1(a.flight.gyro_turn),
                f1(a.flight.launch_estimate),
                f1(a.flight.tilt),
                f1(a.flight.bank),
                a.throw.skips.to_string(),
                format!("{:.1}", a.throw.distance),
            ]
        })
        .collect();
    md_table(
        &[
            "U (m/s)",
            "air",
            "flight (s)",
            "axis turn (°)",
            "∫M⊥/L dt (°)",
            "launch M·t/(I₃ω) (°)",
            "tilt at touch (°)",
            "bank at touch (°)",
            "skips",
            "distance (m)",
        ],
        &body,
    )
}

fn clanet_table(rows: &[OneContact]) -> String {
    let body: Vec<Vec<String>> = rows
        .iter()
        .map(|c| {
            vec![
                format!("{:.0}", c.rev_s),
                format!("{:.1}", 1e3 * c.duration),
                if c.skip { "yes" } else { "no" }.into(),
                format!("{:.1} → {:.1}", c.tilt_in, c.tilt_out),
                format!("{:.1} → {:.1}", c.bank_in, c.bank_out),
                format!("{:.2}", c.axis_turn),
                format!("{:.2}", c.gyro_turn),
                format!("{:.2}", c.momentum_turn),
                sig(c.momentum, 3),
                sig(c.moment_impulse, 3),
                sig(c.impulse, 3),
                format!("{:.1}", 1e3 * c.lever),
                format!("{:.2}", c.nutation),
                format!("{:.1}", c.axis_turn * c.rev_s / 65.0),
            ]
        })
        .collect();
    md_table(
        &[
            "spin (rev/s)",
            "contact (ms)",
            "skips",
            "tilt in → out (°)",
            "bank in → out (°)",
            "axis turn (°)",
            "atan(|ΔL⊥|/L) (°)",
            "L's turn (°)",
            "L = I₃ω (kg m²/s)",
            "|ΔL⊥| (N m s)",
            "water's impulse J (N s)",
            "lever |ΔL⊥|/J (mm)",
            "axis to L after (°)",
            "turn × spin/65",
        ],
        &body,
    )
}

fn zig_table(rows: &[ZigRow], case: &str, unit: &str) -> String {
    let body: Vec<Vec<String>> = rows
        .iter()
        .filter(|z| z.case == case)
        .map(|z| {
            vec![
                format!("{} {unit}", z.value),
                z.shipped.skips.to_string(),
                format!("{} / {}", z.nearby[0], z.nearby[1]),
                landings_cell(&z.shipped, 4),
                z.no_moment.skips.to_string(),
                landings_cell(&z.no_moment, 3),
                z.held.skips.to_string(),
            ]
        })
        .collect();
    md_table(
        &[
            "throw",
            "skips",
            "skips at ∓0.02 m/s",
            "tilt/bank at landings 1–4 (°)",
            "skips, air moment off",
            "tilt/bank, moment off (°)",
            "skips, attitude held",
        ],
        &body,
    )
}

fn report(ctx: &Ctx, r: &Results) -> String {
    let m = &r.moment;
    let mut s = String::new();
    s.push_str("# The stone's attitude, measured and explained\n\n");
    if ctx.quick {
        s.push_str("> Quick run: coarse lists; the full study is `stoneskip study attitude`.\n\n");
    }
    s.push_str(
        "Issue 47, item 4. Measured on the shipped physics (free rigid body, air, smooth lens, the \
         wetted-extent memory; water off, which changes no throw: the stone reads the ambient \
         surface). Attitudes are (tilt, bank) in degrees relative to the travel: tilt > 0 nose up, \
         bank the roll about the travel. Produced by `stoneskip study attitude --out \
         docs/studies/attitude` (`crates/lab/src/study/attitude`).\n\n",
    );

    // 1
    s.push_str("## 1. The air's pitching moment\n\n");
    s.push_str(&format!(
        "The shipped coefficients (C_Lα {:.2}, C_Mα {:.2} /rad about the centre, nose up) put the \
         centre of pressure C_Mα/C_Lα = **{:.3} d ahead of the centre**, {:.3} of the chord from \
         the leading edge, at every α up to 30°. A flat plate's, at small α: thin-aerofoil theory \
         puts it at the quarter chord ({:.3} d ahead, C_Mα = {:.2} at this C_Lα); Jones's \
         slender-wing theory (NACA Report 835, 1946; aspect ratio → 0) for a circle puts it where \
         the span grows, 2R/3 ahead ({:.3} d, C_Mα = {:.2}). The disc's aspect ratio, 4/π = 1.27, \
         lies between the two limits, so a flat disc's centre of pressure at small α sits \
         **ahead of the quarter chord**, and moves aft towards mid-chord as α grows and the flow \
         separates (the low-aspect-ratio flat plates of Winter 1936, NACA TM 798, and Torres & \
         Mueller 2004, AIAA J. 42; Potts & Crowther 2002 note the Frisbee's centre of pressure \
         ahead of its centre too: \"spin provides enhanced pitch stiffness at the expense of roll \
         stability\"). The camber term Hummel fitted (C_M0 ≈ −0.08) is a Frisbee's and rightly \
         dropped: a lens is up–down symmetric. The shipped slope is thus a flat disc's, or a \
         little weaker at small α (it is a Frisbee's measured slope, the camber shifting the \
         moment and not its slope).\n\n",
        m.lift_slope,
        m.moment_slope,
        m.cp_ahead,
        m.cp_from_le,
        CP_THIN_AEROFOIL,
        CP_THIN_AEROFOIL * m.lift_slope,
        CP_SLENDER_CIRCLE,
        CP_SLENDER_CIRCLE * m.lift_slope,
    ));
    s.push_str(
        "The flight of the default stone (100 g lens, R 5 cm, 14 rev/s) from launch to its first \
         touch, with the moment's slope at 0, the shipped value and the two flat-plate limits, and \
         without air. The axis turn is measured; ∫M⊥/L dt is the gyroscope's arithmetic with the \
         model's own moment (a turn of M/(I₃ω) per second); the launch estimate uses the launch \
         moment for the whole flight:\n\n",
    );
    s.push_str(&air_table(&r.air));
    s.push('\n');
    s.push_str(&air_findings(r));

    // 2
    s.push_str("\n## 2. Clanet's disc through one contact\n\n");
    s.push_str(&format!(
        "Clanet, Hersen & Bocquet's disc (R 2.5 cm, e 2.75 mm, 14.6 g) with the default's physics \
         block, at impact U {CLANET_SPEED} m/s, α = β = {CLANET_ANGLE_DEG}°, over spin. The axis \
         turn through the first contact is measured from the orientation; |ΔL⊥|/L is the turn a \
         gyroscope takes from the contact's moment impulse (ΔL the change of the angular \
         momentum, L = I₃ω at entry). The last column multiplies the turn by spin/65: constant \
         when the turn goes as 1/ω.\n\n"
    ));
    s.push_str(&clanet_table(&r.clanet));
    s.push('\n');
    s.push_str(&clanet_findings(r));

    // 3
    s.push_str("\n## 3. Spin and the mean tilt\n\n");
    s.push_str(&format!(
        "The default throw (12 m/s, 20° tilt) over spin: skips with the free body, the mean tilt \
         and bank at its contacts (all contacts, the last included), and skips with the attitude \
         held at that mean tilt. Held at the launch tilt (20°) it makes **{}** skips.\n\n",
        r.held_launch
    ));
    let body: Vec<Vec<String>> = r
        .spin
        .iter()
        .map(|x| {
            vec![
                format!("{}", x.rev_s),
                x.free.skips.to_string(),
                f1(x.mean_tilt),
                f1(x.mean_bank),
                x.held_at_mean.to_string(),
                f1(x.energy_tilt),
                x.held_at_energy.to_string(),
            ]
        })
        .collect();
    s.push_str(&md_table(
        &[
            "spin (rev/s)",
            "skips, free",
            "mean tilt (°)",
            "mean abs(bank) (°)",
            "skips, held at the mean tilt",
            "energy-weighted tilt (°)",
            "skips, held at it",
        ],
        &body,
    ));
    s.push_str("\nHeld attitude against tilt (the default at 12 m/s):\n\n");
    let body: Vec<Vec<String>> = r
        .held_tilts
        .iter()
        .map(|&(t, n)| vec![format!("{t}"), n.to_string()])
        .collect();
    s.push_str(&md_table(&["tilt (°)", "skips, held"], &body));
    s.push_str("\n![skips against spin](spin.png)\n\n");
    s.push_str(&spin_findings(r));

    // 4
    s.push_str("\n## 4. The zig-zags\n\n");
    s.push_str(
        "Each throw with its count at ∓0.02 m/s of launch speed, the tilt/bank at its first \
         landings, and two controls: the air's moment off (lift and drag kept) and the attitude \
         held. All landings of all three are in `landings.csv`.\n\n",
    );
    s.push_str("**The default at 12 m/s over mass:**\n\n");
    s.push_str(&zig_table(&r.zig, "mass", "kg"));
    if !r.mass_sweep.is_empty() {
        s.push_str("\nA finer mass sweep (`mass_sweep.csv`): mass, skips, tilt/bank at the second landing:\n\n");
        let body: Vec<Vec<String>> = r
            .mass_sweep
            .iter()
            .map(|&(m, n, t, b)| vec![format!("{m:.3}"), n.to_string(), f1(t), f1(b)])
            .collect();
        s.push_str(&md_table(
            &[
                "mass (kg)",
                "skips",
                "2nd landing tilt (°)",
                "2nd landing bank (°)",
            ],
            &body,
        ));
    }
    s.push_str("\n**The default at 13 and 15 m/s:**\n\n");
    s.push_str(&zig_table(&r.zig, "speed", "m/s"));
    if r.zig.iter().any(|z| z.case == "record") {
        s.push_str("\n**The record throw at 22 and 23 m/s:**\n\n");
        s.push_str(&zig_table(&r.zig, "record", "m/s"));
    }
    s.push('\n');
    s.push_str(&zig_findings(r));
    s
}

fn air_findings(r: &Results) -> String {
    let find = |u: f64, m: Option<f64>| {
        r.air.iter().find(|a| {
            a.speed == u
                && match m {
                    Some(m) => a.variant == Variant::Shipped && (a.moment_slope - m).abs() < 1e-12,
                    None => a.variant == Variant::NoAir,
                }
        })
    };
    let mut s = String::new();
    for u in [12.0, 15.0] {
        if let (Some(a), Some(o)) = (find(u, Some(r.moment.moment_slope)), find(u, Some(0.0))) {
            s.push_str(&format!(
                "- At {u} m/s the axis turns **{:.1}°** in {:.2} s of flight (the gyroscope's \
                 arithmetic with the model's moment: {:.1}°) and the stone lands at tilt {:.1}°, \
                 **bank {:.1}°**: {} skips. With the moment off it lands at {:.1}°/{:.1}°: {} \
                 skips{}.\n",
                a.flight.axis_turn,
                a.flight.time,
                a.flight.gyro_turn,
                a.flight.tilt,
                a.flight.bank,
                a.throw.skips,
                o.flight.tilt,
                o.flight.bank,
                o.throw.skips,
                find(u, None).map_or(String::new(), |n| format!(
                    "; without air {} skips",
                    n.throw.skips
                )),
            ));
        }
    }
    s.push_str(
        "\n**Finding 1 — physics** (a flat plate's centre of pressure: thin-aerofoil theory and \
         Jones's slender-wing theory, NACA Report 835, bracket a flat disc's ahead of the quarter \
         chord; Potts & Crowther 2002 and Crowther & Potts 2007 for the spinning disc: a nose-up \
         moment about the pitch axis precesses the axis about the roll axis at M/(I₃ω), a \
         Frisbee's roll). The shipped pitching moment is a flat disc's, or a little weaker: its \
         centre of pressure (0.225 d ahead) is behind both theoretical limits at small α, and \
         near where a separated flat plate's sits at 20° (its centre of pressure moves aft with \
         α). The integrator reproduces the gyroscope's arithmetic (the axis turn and ∫M⊥/L dt \
         agree within a few per cent). So the roll before the first touch is the model's \
         physics, not an error: the default (14 rev/s, 20° of tilt held against the air for a \
         third of a second) rolls about 25° at 12 m/s and 45° at 15 m/s, and a flat plate's \
         larger moment would roll it more (the C_Mα 0.48 and 0.64 rows). Nothing was changed in \
         `air.rs` or in the presets, so no preset's meaning changed.\n",
    );
    s
}

fn clanet_findings(r: &Results) -> String {
    let mut s = String::new();
    if let Some(c) = r.clanet.iter().find(|c| (c.rev_s - 65.0).abs() < 1e-9) {
        s.push_str(&format!(
            "- At 65 rev/s the contact lasts {:.1} ms; the tilt goes {:.1}° → {:.1}° and the bank \
             {:.1}° → {:.1}°: the axis turns **{:.2}°**, and the angular momentum turns \
             {:.2}° (the axis stays on L within {:.2}°). The water's impulse {} N s acts {:.1} mm \
             ({:.0} % of the radius) behind the centre: |ΔL⊥| = {} N m s against L = I₃ω = {} \
             kg m²/s, a turn of atan(|ΔL⊥|/L) = {:.1}° at constant spin (more as the contact's \
             friction takes spin away).\n",
            1e3 * c.duration,
            c.tilt_in,
            c.tilt_out,
            c.bank_in,
            c.bank_out,
            c.axis_turn,
            c.momentum_turn,
            c.nutation,
            sig(c.impulse, 3),
            1e3 * c.lever,
            100.0 * c.lever / stoneskip_reference::CLANET_RADIUS,
            sig(c.moment_impulse, 3),
            sig(c.momentum, 3),
            c.gyro_turn,
        ));
    }
    let k: Vec<f64> = r
        .clanet
        .iter()
        .map(|c| c.axis_turn * c.rev_s / 65.0)
        .collect();
    if let (Some(lo), Some(hi)) = (
        k.iter().copied().reduce(f64::min),
        k.iter().copied().reduce(f64::max),
    ) {
        s.push_str(&format!(
            "- Over {} the turn × spin/65 stays within {:.1}–{:.1}°: the turn goes as 1/ω, so α \
             becomes constant as the spin grows, Clanet's high-spin limit, and not at 65 rev/s.\n",
            r.clanet
                .iter()
                .map(|c| format!("{:.0}", c.rev_s))
                .collect::<Vec<_>>()
                .join(", ")
                + " rev/s",
            lo,
            hi,
        ));
    }
    s.push_str(
        "\n**Finding 2 — physics** (the gyroscope, ΔL = ∫M dt with L = I₃ω; Clanet, Hersen & \
         Bocquet, Nature 427, 2004: α constant in the high-spin limit): the attitude change \
         through one contact is exactly the turn of the angular momentum by the contact's moment \
         impulse, and it falls as 1/ω. \"α stays constant\" is the limit ω → ∞; at Clanet's 65 \
         rev/s the arithmetic itself, with the lift acting half a radius behind the centre, \
         gives a turn of about 13°. The lever is the contact law's (each wetted face's pressure \
         at its area centroid, the paper's eqs. 25–26); a pressure centre further forward \
         would turn it less. That is a question for the contact law, not checked here.\n",
    );
    s
}

fn spin_findings(r: &Results) -> String {
    let mut s = String::new();
    let held_tilt = |t: f64| {
        r.held_tilts
            .iter()
            .find(|x| (x.0 - t).abs() < 1e-9)
            .map(|x| x.1)
    };
    if let Some(peak) = r.spin.iter().max_by_key(|x| x.free.skips) {
        s.push_str(&format!(
            "- The free count peaks at {} rev/s with **{}** skips at a mean tilt of **{:.1}°** \
             (mean |bank| {:.1}°); held at that tilt the stone makes **{}**; held at the launch \
             tilt, {}.\n",
            peak.rev_s,
            peak.free.skips,
            peak.mean_tilt,
            peak.mean_bank,
            peak.held_at_mean,
            r.held_launch
        ));
    }
    for x in r.spin.iter().filter(|x| x.rev_s >= 100.0) {
        s.push_str(&format!(
            "- At {} rev/s: {} skips free (held at the launch tilt: {}; within max(2, 20 %): {}), \
             mean tilt {:.1}°, yet held at that tilt {}.\n",
            x.rev_s,
            x.free.skips,
            r.held_launch,
            if (x.free.skips as f64 - r.held_launch as f64).abs()
                <= 2f64.max(0.2 * r.held_launch as f64)
            {
                "yes"
            } else {
                "no"
            },
            x.mean_tilt,
            x.held_at_mean
        ));
    }
    for x in r.spin.iter().filter(|x| x.mean_bank > 60.0) {
        s.push_str(&format!(
            "- At {} rev/s the stone banks steeply or turns over (mean |bank| {:.0}°) and makes {} skips: its mean \
             tilt is not an attitude it holds, and the held count beside it means nothing.\n",
            x.rev_s, x.mean_bank, x.free.skips
        ));
    }
    if let Some(t) = held_tilt(2.5) {
        s.push_str(&format!(
            "- Held nose-flat (2.5°) the default makes {t} skips.\n"
        ));
    }
    let seq = |rev: f64| {
        r.spin.iter().find(|x| x.rev_s == rev).map(|x| {
            x.free
                .landings
                .iter()
                .take(10)
                .map(|l| format!("{:.0}/{:.0}", l.tilt, l.bank))
                .collect::<Vec<_>>()
                .join(", ")
        })
    };
    for rev in [20.0, 150.0] {
        if let Some(q) = seq(rev) {
            s.push_str(&format!(
                "- Tilt/bank at the first ten landings, {rev} rev/s: {q}.\n"
            ));
        }
    }
    s.push_str(
        "\nThe landings (`landings.csv`, case `spin`) show two regimes. At 10–30 rev/s the first \
         one or two contacts turn the stone by 10–20° (a turn ∝ 1/ω, Finding 2) and it settles \
         at a trim of a few degrees of tilt and bank, where it stays for the rest of the throw: \
         there the held stone makes as many skips, so **the mean tilt explains the peak**. From \
         ~50 rev/s each contact turns it only a few degrees, and the axis circles slowly about \
         the same trim with the launch offset as its radius, undamped, as a fast top precesses \
         about its equilibrium (the 150 rev/s landings above): it passes through nose-flat, \
         where a held stone makes no skips, and stops. The mean tilt is then the trim, not the \
         attitude of the contacts, and does not explain the count; the count returns to the \
         held attitude's at the launch tilt.\n\n\
         **Finding 3 — physics** (the gyroscope: a contact's turn is its moment impulse over \
         I₃ω, Finding 2; Bocquet, Am. J. Phys. 71, 2003: the count is capped by the attitude's \
         stability; Rosellini et al., JFM 543, 2005: no spin, the stone dives). The peak at \
         15–20 rev/s is the stone laid flat to its trim by its first contacts; no measurement of \
         skips against spin was found to compare it with (first_bounce_memory.md §5). The trim \
         and the size of each turn come from the contact's moment (its lever), the contact \
         law's part.\n",
    );
    s
}

fn zig_findings(r: &Results) -> String {
    let mut s = String::new();
    let jumpy: Vec<String> = r
        .zig
        .iter()
        .filter(|z| {
            let n = z.shipped.skips as i64;
            z.nearby.iter().any(|&k| (k as i64 - n).abs() > 1)
        })
        .map(|z| format!("{} {}", z.case, z.value))
        .collect();
    s.push_str(&format!(
        "- Throws whose count moves by more than 1 within ±0.02 m/s of launch speed: {}.\n",
        if jumpy.is_empty() {
            "none".to_owned()
        } else {
            jumpy.join(", ")
        }
    ));
    let list = |case: &str, f: &dyn Fn(&ZigRow) -> usize| {
        r.zig
            .iter()
            .filter(|z| z.case == case)
            .map(|z| f(z).to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    s.push_str(&format!(
        "- Skips over mass (shipped): {}; the air's moment off: {}; the attitude held: {}.\n",
        list("mass", &|z| z.shipped.skips),
        list("mass", &|z| z.no_moment.skips),
        list("mass", &|z| z.held.skips),
    ));
    s.push_str(&format!(
        "- Skips at 13, 15 m/s (shipped): {}; moment off: {}; held: {}.\n",
        list("speed", &|z| z.shipped.skips),
        list("speed", &|z| z.no_moment.skips),
        list("speed", &|z| z.held.skips),
    ));
    if r.zig.iter().any(|z| z.case == "record") {
        s.push_str(&format!(
            "- The record throw at 22, 23 m/s (shipped): {}; moment off: {}; held: {}.\n",
            list("record", &|z| z.shipped.skips),
            list("record", &|z| z.no_moment.skips),
            list("record", &|z| z.held.skips),
        ));
    }
    s.push_str("\nThe landing at which each throw stopped (its last contact):\n\n");
    let body: Vec<Vec<String>> = r
        .zig
        .iter()
        .filter_map(|z| {
            let l = z.shipped.landings.last()?;
            Some(vec![
                format!("{} {}", z.case, z.value),
                z.shipped.landings.len().to_string(),
                format!("{:.1}", l.speed),
                format!("{:.1}", l.beta),
                format!("{:.1} → {:.1}", l.tilt, l.tilt_out),
                format!("{:.1} → {:.1}", l.bank, l.bank_out),
            ])
        })
        .collect();
    s.push_str(&md_table(
        &[
            "throw",
            "contact",
            "speed (m/s)",
            "β (°)",
            "tilt in → out (°)",
            "bank in → out (°)",
        ],
        &body,
    ));
    s.push_str(
        "\nWhat decides each: the fast throws land steeply banked after the air's roll (Finding \
         1) or after a contact's turn, and dig in; over mass the landing attitudes move smoothly \
         (the finer sweep's second landing changes by a degree or two per 5 g) but the count \
         steps where a landing comes in nose-flat or nose-down at a shallow angle, or steeply \
         tilted or banked, and the contact does not lift it out (the table above). The air's precession rate M/(I₃ω) falls \
         as 1/m (I₃ ∝ m; the moment does not depend on the mass), so the bank at the first \
         touch falls with mass and every later landing moves with it.\n\n\
         **Finding 4 — physics** (the gyroscope in the air and in the contacts, Findings 1–2; a \
         stone landing nose-down or steeply banked dives: Clanet et al. 2004, Rosellini et al. \
         2005). The zig-zags are a count that steps when a landing attitude, which itself moves \
         smoothly with mass or speed, crosses into a nose-flat or steeply banked touch: a \
         sensitivity of a free spinning body to its landing attitude, not chaos in the launch \
         (the counts hold at ±0.02 m/s but for the record throw at 22 m/s) and not an air \
         moment that is wrong (it is a flat disc's). With the moment off or the attitude held \
         the trends are smooth, which shows where the sensitivity enters, not that the moment \
         should be off. What is the model's own and open: the contact's moment lever (Finding \
         2), which sets each contact's turn and the trim.\n",
    );
    s
}
