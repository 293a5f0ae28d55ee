//! The fidelity study's results and report: its CSVs, charts and README (each section's
//! Markdown, the lead table of checks against the published behaviour), from the [`Fidelity`]
//! that `compute` measured.

use super::*;

/// §4's CSVs: the record class's throws and the record run's tail.
pub(super) fn write_record_csvs(ctx: &Ctx, f: &Fidelity) -> Result<(), StudyError> {
    let mut c = Csv::new(&SHAPE_HEADER);
    for r in &f.record {
        c.push(shape_row(&format!("{} m/s", r.speed), &r.shape));
    }
    if !c.is_empty() {
        ctx.write_csv("record_class.csv", &c)?;
    }
    let mut c = Csv::new(&[
        "speed_m_s",
        "contact",
        "speed_in_m_s",
        "beta_in_deg",
        "tilt_in_deg",
        "contact_s",
        "exit_angle_deg",
        "hop_m",
        "flight_m",
        "in_contact_m",
    ]);
    for r in &f.record {
        for h in &r.tail {
            c.push(vec![
                r.speed.into(),
                h.contact.into(),
                h.speed_in.into(),
                h.beta_in.into(),
                h.tilt_in.into(),
                h.contact_s.into(),
                h.exit_angle.into(),
                h.hop.into(),
                h.flight.into(),
                h.in_contact.into(),
            ]);
        }
    }
    if !c.is_empty() {
        ctx.write_csv("record_tail.csv", &c)?;
    }
    Ok(())
}

pub(super) fn shape_row(label: &str, t: &ThrowShape) -> Vec<Val> {
    vec![
        label.into(),
        t.skips.into(),
        t.distance.into(),
        t.final_share.into(),
        t.final_duration.into(),
        t.longest_earlier_contact.into(),
        t.tail_longest_hop.into(),
        t.lateral.into(),
    ]
}

pub(super) const SHAPE_HEADER: [&str; 8] = [
    "case",
    "skips",
    "distance_m",
    "final_share",
    "final_contact_s",
    "longest_earlier_contact_s",
    "tail_longest_hop_m",
    "lateral_m",
];

pub(super) fn write_csvs(ctx: &Ctx, f: &Fidelity) -> Result<(), StudyError> {
    let mut c = Csv::new(&[
        "law",
        "contact",
        "vz_in",
        "vz_out",
        "restitution",
        "speed_ratio",
    ]);
    for b in &f.bounces {
        c.push(vec![
            law_name(b.law).into(),
            b.index.into(),
            b.vz_in.into(),
            b.vz_out.into(),
            b.restitution.into(),
            b.speed_ratio.into(),
        ]);
    }
    ctx.write_csv("energy_per_contact.csv", &c)?;
    let mut c = Csv::new(&SHAPE_HEADER);
    c.push(shape_row("locked", &f.locked));
    for r in &f.spin {
        c.push(shape_row(&format!("free {} rev/s", r.rev_per_s), &r.shape));
    }
    for l in &f.locked_tilts {
        c.push(shape_row(&format!("locked tilt {}°", l.tilt_deg), &l.shape));
    }
    ctx.write_csv("spin_sweep.csv", &c)?;
    let mut c = Csv::new(&[
        "rev_per_s",
        "skips",
        "median_skips",
        "min_skips",
        "max_skips",
        "members",
        "tilt_after_first_deg",
    ]);
    for r in &f.spin {
        c.push(vec![
            r.rev_per_s.into(),
            r.shape.skips.into(),
            r.median().into(),
            (*r.members.first().unwrap_or(&0)).into(),
            (*r.members.last().unwrap_or(&0)).into(),
            r.members.len().into(),
            if r.tilt_after_first.is_finite() {
                r.tilt_after_first.into()
            } else {
                "".into()
            },
        ]);
    }
    ctx.write_csv("spin_ensemble.csv", &c)?;
    let mut c = Csv::new(&[
        "launch_tilt_deg",
        "rev_per_s",
        "skips",
        "median",
        "min",
        "max",
        "locked_skips",
    ]);
    for (tilt, runs) in &f.spin_tilts {
        let locked = locked_at(&f.locked_tilts, *tilt)?;
        for r in runs {
            c.push(vec![
                (*tilt).into(),
                r.rev_per_s.into(),
                r.shape.skips.into(),
                r.median().into(),
                r.members.first().copied().unwrap_or(0).into(),
                r.members.last().copied().unwrap_or(0).into(),
                locked.skips.into(),
            ]);
        }
    }
    ctx.write_csv("spin_tilts.csv", &c)?;
    let mut c = Csv::new(&[
        "rev_per_s",
        "contact",
        "turn_deg",
        "inclination_change_deg",
        "dvz",
        "lever_mm",
    ]);
    for t in &f.turns {
        c.push(vec![
            t.rev_per_s.into(),
            t.index.into(),
            t.turn_deg.into(),
            t.inclination_change_deg.into(),
            t.dvz.into(),
            t.lever_mm.into(),
        ]);
    }
    ctx.write_csv("precession_per_contact.csv", &c)?;
    let mut c = Csv::new(&["rev_per_s", "friction", "near_field", "touchdown", "y_m"]);
    for r in &f.curve {
        for &(n, y) in &r.lateral {
            c.push(vec![
                r.rev_per_s.into(),
                r.friction.into(),
                r.near_field.into(),
                n.into(),
                y.into(),
            ]);
        }
    }
    ctx.write_csv("curve.csv", &c)?;
    let mut c = Csv::new(&SHAPE_HEADER);
    for n in &f.near {
        c.push(shape_row(&n.label, &n.shape));
    }
    ctx.write_csv("near_field.csv", &c)?;
    write_record_csvs(ctx, f)?;
    let mut c = Csv::new(&[
        "tilt_deg",
        "u_min_before",
        "u_min_free_only",
        "u_min_buoyancy_only",
        "u_min_after",
    ]);
    for a in &f.anchors {
        let v = |u: Option<f64>| Val::F(u.unwrap_or(f64::NAN));
        c.push(vec![
            a.tilt_deg.into(),
            v(a.before),
            v(a.free_only),
            v(a.buoyancy_only),
            v(a.after),
        ]);
    }
    ctx.write_csv("magic_angle.csv", &c)?;
    let mut c = Csv::new(&SHAPE_HEADER);
    for p in &f.presets {
        c.push(shape_row(&format!("{} before", p.stem), &p.before));
        c.push(shape_row(&format!("{} after", p.stem), &p.after));
    }
    ctx.write_csv("presets.csv", &c)?;
    air::write_csvs(ctx, &f.air)?;
    limit::write_csvs(ctx, &f.limit)?;
    grid::write_csvs(ctx, &f.grid)?;
    tick::write_csvs(ctx, &f.tick)?;
    accel::write_csvs(ctx, &f.accel)
}

pub(super) fn write_charts(ctx: &Ctx, f: &Fidelity) -> Result<(), StudyError> {
    let pts = |g: &dyn Fn(&SpinRun) -> f64| -> Vec<(f64, f64)> {
        f.spin.iter().map(|r| (r.rev_per_s, g(r))).collect()
    };
    let skips = Chart::new(
        "Default throw: skips against spin (free rigid body)",
        "spin (rev/s)",
        "skips",
    )
    .series(Series::new(
        "free",
        pts(&|r| r.shape.skips as f64),
        colors::BLUE,
        Mark::LinePoints,
    ))
    .series(Series::new(
        "free, median over launch heights",
        pts(&|r| r.median() as f64),
        colors::GREEN,
        Mark::LinePoints,
    ))
    .line(RefLine::h(
        "locked (infinite spin)",
        f.locked.skips as f64,
        colors::RED,
    ))
    .legend(Legend::UpperRight);
    let share = Chart::new(
        "Share of the distance in the last contact",
        "spin (rev/s)",
        "share",
    )
    .series(Series::new(
        "free",
        pts(&|r| r.shape.final_share),
        colors::BLUE,
        Mark::LinePoints,
    ))
    .line(RefLine::h("issue 11 limit", MAX_FINAL_SHARE, colors::GREY))
    .legend(Legend::UpperLeft);
    plot::draw(
        &ctx.path("spin_sweep.png"),
        (1400, 560),
        2,
        None,
        &[Panel::Chart(skips), Panel::Chart(share)],
    )?;
    let flat: Vec<&CurveRun> = f.curve.iter().filter(|r| !r.near_field).collect();
    let mut by_touchdown = Chart::new(
        "The curve on flat water: sideways position at each touchdown",
        "touchdown",
        "y (m)",
    )
    .legend(Legend::UpperLeft);
    for (k, r) in flat.iter().filter(|r| r.friction).enumerate() {
        by_touchdown = by_touchdown.series(Series::new(
            format!("{:+} rev/s", r.rev_per_s),
            r.lateral.iter().take(CURVE_TOUCHDOWNS).copied().collect(),
            colors::CYCLE[k % colors::CYCLE.len()],
            Mark::LinePoints,
        ));
    }
    let at = |friction: bool| -> Vec<(f64, f64)> {
        flat.iter()
            .filter(|r| r.friction == friction && r.rev_per_s > 0.0)
            .filter_map(|r| Some((r.rev_per_s, r.y_at(CURVE_AT)?)))
            .collect()
    };
    let by_spin = Chart::new(
        format!("Sideways position at touchdown {CURVE_AT} against spin (flat water)"),
        "spin (rev/s)",
        "y (m)",
    )
    .series(Series::new(
        "friction on",
        at(true),
        colors::BLUE,
        Mark::LinePoints,
    ))
    .series(Series::new(
        "friction off (gyroscopic part)",
        at(false),
        colors::ORANGE,
        Mark::Dashed,
    ))
    .legend(Legend::UpperLeft);
    plot::draw(
        &ctx.path("curve.png"),
        (1400, 560),
        2,
        None,
        &[Panel::Chart(by_touchdown), Panel::Chart(by_spin)],
    )?;
    accel::write_chart(ctx, &f.accel)
}

pub(super) fn verdict(ok: bool) -> &'static str {
    if ok {
        "yes"
    } else {
        "**no**"
    }
}

/// The lead table's "no hovercraft" rows: the shipped presets, and §9's finer columns.
pub(super) fn hovercraft_rows(f: &Fidelity) -> Vec<Vec<String>> {
    let mut rows = Vec::new();
    let glides = f.presets.iter().filter(|p| p.glide.is_some()).count();
    rows.push(vec![
        "no hovercraft in any shipped preset that skips twice (issue 11)".into(),
        format!(
            "{} presets fail",
            f.presets
                .iter()
                .filter(|p| hovercraft(&p.before, MAX_FINAL_SHARE, MAX_EARLIER_CONTACT).is_some())
                .count()
        ),
        if glides == 0 {
            "none fails".to_owned()
        } else {
            format!(
                "{glides} fail: {}",
                f.presets
                    .iter()
                    .filter(|p| p.glide.is_some())
                    .map(|p| if p.paper_model {
                        format!("{} (the paper's own locked model on flat water)", p.stem)
                    } else {
                        p.stem.to_owned()
                    })
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        },
    ]);
    rows.push(vec![
        "…and on finer columns, where the near field should converge (§9)".into(),
        "—".into(),
        grid::lead_words(&f.grid),
    ]);
    rows.push(vec![
        "…and as the stone–water coupling tick shrinks (§11)".into(),
        "—".into(),
        tick::lead_words(&f.tick),
    ]);
    rows
}

pub(super) fn lead_table(f: &Fidelity) -> String {
    let mut rows = Vec::new();
    let d = f.presets.iter().find(|p| p.stem == "default");
    if let Some(d) = d {
        rows.push(vec![
            "no steady planing well above the minimal speed (Hewitt 2011)".into(),
            format!(
                "default throw: last contact {:.0} % of {:.1} m",
                100.0 * d.before.final_share,
                d.before.distance
            ),
            format!(
                "{:.0} % of {:.1} m",
                100.0 * d.after.final_share,
                d.after.distance
            ),
        ]);
    }
    rows.extend(hovercraft_rows(f));
    if let Some(r) = f.record.first() {
        rows.push(vec![
            "record class: ~19 m/s, tens of skips over ~60–120 m (§3)".into(),
            "17 skips in 34 m, then an 83 m glide (issue 11, old record preset)".into(),
            format!("{} skips over {:.0} m", r.shape.skips, r.shape.distance),
        ]);
        rows.push(vec![
            "a quick pitty-pat tail: last-quarter hops < 0.5 m".into(),
            "a planing glide instead".into(),
            format!(
                "longest last-quarter hop {:.2} m ({}){}",
                r.shape.tail_longest_hop,
                verdict(r.shape.tail_longest_hop < 0.5),
                tail_split_words(&r.tail).map_or(String::new(), |w| format!("; {w} (§4)"))
            ),
        ]);
    }
    let drops = spin_drops(&f.spin);
    let at20 = f
        .spin
        .iter()
        .find(|r| r.rev_per_s == 20.0)
        .map(|r| r.shape.skips);
    rows.push(vec![
        "more spin never means fewer skips (Tang 2021; Clanet 2004)".into(),
        "6 skips at 60 rad/s, 3 at 120, 2 at 300 (issue 11)".into(),
        format!(
            "{drops} drops of the {}-throw median over 0–{} rev/s ({})",
            f.spin.first().map_or(1, |r| r.members.len()),
            f.spin.last().map_or(0.0, |r| r.rev_per_s),
            verdict(drops == 0)
        ),
    ]);
    if let Some(s20) = at20 {
        rows.push(vec![
            "spin saturates: at 20 rev/s ≥ 70 % of the locked count".into(),
            "—".into(),
            format!(
                "{s20} against {} locked ({})",
                f.locked.skips,
                verdict(s20 as f64 >= 0.7 * f.locked.skips as f64)
            ),
        ]);
    }
    let facts = curve_facts(f);
    rows.push(vec![
        "the path curves towards the spin, more with each bounce; reversed spin mirrors it (Tang 2021)"
            .into(),
        "locked attitude: no curve (the stone cannot bank)".into(),
        format!(
            "flat water, touchdown {CURVE_AT}: {} rev/s (+y: the leading edge's side); mirror to {}",
            facts.sides(""),
            sig(facts.mirror, 2)
        ),
    ]);
    rows.push(vec![
        "the paper's law gains no energy (paper.ron)".into(),
        format!(
            "as printed: leaves a contact {:.2}× faster",
            f.paper.as_printed
        ),
        format!(
            "energy-consistent: at most {:.2}× ({})",
            f.paper.opposing,
            verdict(f.paper.opposing <= 1.0)
        ),
    ]);
    let best = |g: &dyn Fn(&Anchor) -> Option<f64>| {
        f.anchors
            .iter()
            .filter_map(|a| g(a).map(|u| (a.tilt_deg, u)))
            .fold(
                (f64::NAN, f64::INFINITY),
                |b, x| if x.1 < b.1 { x } else { b },
            )
    };
    let (tb, ub) = best(&|a| a.before);
    let (ta, ua) = best(&|a| a.after);
    rows.push(vec![
        "magic angle: lowest U_min near α = 20°, ≈ 2.5 m/s (Clanet 2004)".into(),
        format!("{tb}°, {} m/s (locked)", sig(ub, 3)),
        format!("{ta}°, {} m/s (free, 65 rev/s)", sig(ua, 3)),
    ]);
    let rolls: Vec<String> = f
        .air
        .rolls
        .iter()
        .map(|r| {
            format!(
                "{}° at {} rev/s",
                sig(r.bank_deg.abs(), 2),
                sig(r.rev_per_s, 3)
            )
        })
        .collect();
    rows.push(vec![
        "a stone that stays long in the air rolls onto its side (Steiner, whole_throw.md §3)"
            .into(),
        "no air: a torque-free flight, no roll".into(),
        format!("bank at the first touch (§7): {}", rolls.join(", ")),
    ]);
    let (before, after) = accel::lead_words(&f.accel);
    rows.push(vec![
        "a bounce needs a peak acceleration of about 4 g (Tang 2021: 3.80 g; §12)".into(),
        before,
        after,
    ]);
    md_table(
        &["reference behaviour", "model before", "model after"],
        &rows,
    )
}

pub(super) fn report(ctx: &Ctx, f: &Fidelity) -> String {
    let mut s = String::from("# Whole-throw fidelity (issue 11)\n\n");
    s.push_str(
        "Before: the paper's high-spin limit as the presets used it (attitude locked, flat water, \
         no buoyancy, no air). After: the shipped presets' model (free rigid body, smooth surface \
         of revolution whose mesh meets the water in a Résal frame, Archimedes on every wetted \
         face, the air in flight, wavy contact on 2 cm columns). Same throws.\n\n",
    );
    if ctx.quick {
        s.push_str(&format!(
            "*Quick run (`--quick`): coarse sweeps, near-field water on {} cm columns.*\n\n",
            QUICK_CELL * 100.0
        ));
    }
    s.push_str(&lead_table(f));
    s.push_str(&energy_section(f));
    s.push_str(&spin_section(f));
    s.push_str(&near_section(f));
    s.push_str(&record_section(f));
    s.push_str(&anchor_section(f));
    s.push_str(&preset_section(f));
    s.push_str(&air::section(&f.air, &f.spin));
    s.push_str(&limit::section(&f.limit, &quoted(f)));
    s.push_str(&grid::section(&f.grid));
    s.push_str(RETIRED_SECTION_10);
    s.push_str(&tick::section(&f.tick));
    s.push_str(&accel::section(&f.accel));
    s
}

/// §10 ran the shipped throws on the spectral near field, since retired; the numbering stays.
pub(super) const RETIRED_SECTION_10: &str = "\n## 10. A deep-water near field (retired)\n\nThis section ran \
     the shipped throws on the spectral near field (`water.near_field: Spectral`, linear potential \
     flow with the capillary–gravity dispersion relation on a patch that followed the stone). The \
     stone now reads only the ambient water (the wetted-extent memory, issue 38), the option is \
     retired, and its tables are kept in docs/studies/retired.md with the tag that still runs it.\n";

/// The numbers of §2 that §8's explanation quotes.
pub(super) fn quoted(f: &Fidelity) -> Quoted {
    let firsts: Vec<&AxisTurn> = f.turns.iter().filter(|t| t.index == 1).collect();
    let mean = |of: fn(&AxisTurn) -> f64| {
        (!firsts.is_empty())
            .then(|| firsts.iter().map(|t| of(t)).sum::<f64>() / firsts.len() as f64)
    };
    Quoted {
        launch_tilt: f.launch_tilt,
        first_turn_times_spin: mean(|t| t.turn_deg * t.rev_per_s),
        first_lever: mean(|t| t.lever_mm).map(|mm| (mm, 1e3 * f.radius)),
        shallow_locked: f.locked_tilts.first().map(|l| (l.tilt_deg, l.shape.skips)),
        launch_locked: f.locked.skips,
        tilt_check: f
            .spin_tilts
            .first()
            .map(|(tilt, runs)| (*tilt, spin_drops(runs))),
    }
}

pub(super) fn energy_section(f: &Fidelity) -> String {
    let mut s = String::from(
        "\n## 1. The vertical energy budget of a contact\n\nThe default throw with the locked \
         attitude on flat water, each law at its default coefficients. Restitution is \
         v_z,out/|v_z,in|; a speed ratio above 1 would be energy from nowhere.\n\n",
    );
    let mut rows = Vec::new();
    for b in f.bounces.iter().filter(|b| b.index <= 6) {
        rows.push(vec![
            law_name(b.law).into(),
            b.index.to_string(),
            sig(b.vz_in, 3),
            sig(b.vz_out, 3),
            sig(b.restitution, 3),
            sig(b.speed_ratio, 4),
        ]);
    }
    s.push_str(&md_table(
        &[
            "law",
            "contact",
            "v_z in",
            "v_z out",
            "restitution",
            "speed out/in",
        ],
        &rows,
    ));
    s.push_str(&format!(
        "\nMean over the skips listed: vertical restitution {}, speed out/in {}. A law \
         whose pressure grows with the normal velocity (Rosellini's U·v_n, the paper's v_n²) pushes \
         harder going in than coming out, so every contact returns less vertical speed than it \
         took and the exit angles shrink towards planing; Bocquet's U² with C_f = 1 loses the most \
         speed per contact through friction.\n\n\
         The paper preset as printed (pressure along −N on receding faces) leaves a contact up to \
         {:.3}× faster than it entered ({} skips); read energy-consistently (each face's pressure \
         opposes its own normal motion) at most {:.3}× ({} skips).\n",
        mean_by_law(&f.bounces, |b| b.restitution),
        mean_by_law(&f.bounces, |b| b.speed_ratio),
        f.paper.as_printed, f.paper.skips_as_printed, f.paper.opposing, f.paper.skips_opposing
    ));
    s
}

/// "Rosellini 0.68, Paper 0.51, …": the mean of `g` over each law's bounces.
pub(super) fn mean_by_law(bounces: &[Bounce], g: impl Fn(&Bounce) -> f64) -> String {
    ForceLaw::ALL
        .iter()
        .filter_map(|&law| {
            let v: Vec<f64> = bounces.iter().filter(|b| b.law == law).map(&g).collect();
            (!v.is_empty()).then(|| {
                format!(
                    "{} {}",
                    law_name(law),
                    sig(v.iter().sum::<f64>() / v.len() as f64, 3)
                )
            })
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The ensemble's launch-height step (m).
pub(super) fn ensemble_step() -> f64 {
    ensemble_offsets(false)
        .iter()
        .map(|d| d.abs())
        .filter(|d| *d > 0.0)
        .fold(f64::INFINITY, f64::min)
}

/// What the sweep says about the fall of the count at high spin: the locked count against tilt,
/// and the tilt the free stone keeps through its first contact on either side of the fall.
pub(super) fn spin_mechanism(f: &Fidelity) -> String {
    let mut s = String::from(
        "\n### Why the count falls at high spin\n\nThe same throw with its attitude held (the \
         high-spin limit) at other tilts:\n\n",
    );
    let rows: Vec<Vec<String>> = f
        .locked_tilts
        .iter()
        .map(|l| {
            vec![
                sig(l.tilt_deg, 3),
                l.shape.skips.to_string(),
                sig(l.shape.distance, 3),
                format!("{:.0} %", 100.0 * l.shape.final_share),
            ]
        })
        .collect();
    s.push_str(&md_table(
        &["locked tilt (°)", "skips", "distance (m)", "last contact"],
        &rows,
    ));
    // The largest fall of the median from one spin to the next.
    let fall = f
        .spin
        .windows(2)
        .filter(|w| w[1].median() < w[0].median())
        .max_by_key(|w| w[0].median() - w[1].median());
    let fall =
        fall.filter(|w| w[0].tilt_after_first.is_finite() && w[1].tilt_after_first.is_finite());
    if let Some(w) = fall {
        let (a, b) = (&w[0], &w[1]);
        s.push_str(&format!(
            "\nThe median falls most between {} and {} rev/s ({} → {} skips). Leaving the first, \
             hardest contact the stone is tilted {}° at {} rev/s and {}° at {} rev/s.",
            sig(a.rev_per_s, 3),
            sig(b.rev_per_s, 3),
            a.median(),
            b.median(),
            sig(a.tilt_after_first, 2),
            sig(a.rev_per_s, 3),
            sig(b.tilt_after_first, 2),
            sig(b.rev_per_s, 3),
        ));
        if a.tilt_after_first < 0.6 * b.tilt_after_first {
            s.push_str(
                " Below the fall that contact pitches the nose down to a shallow tilt (its torque \
                 impulse J·ℓ is not small against the spin's angular momentum, so it turns the stone \
                 itself); above it the gyroscope keeps most of the launch tilt.",
            );
        }
        s.push_str(&clanet_turn_words(f));
        let shallow = f.locked_tilts.first();
        let launch = f.locked_tilts.iter().find(|l| l.tilt_deg == 20.0);
        let lowered = a.tilt_after_first < 0.6 * b.tilt_after_first;
        if let (Some(lo), Some(l20), true) = (shallow, launch, lowered) {
            if lo.shape.skips > l20.shape.skips {
                s.push_str(&format!(
                    " A shallow tilt held through the run is worth more skips on the near field than \
                     the launch's 20° ({} at {}° against {} at 20°, locked), so here moderate spin, \
                     which lets the first contact lower the tilt, beats high spin, which keeps it.",
                    lo.shape.skips,
                    sig(lo.tilt_deg, 2),
                    l20.shape.skips
                ));
            }
        }
        if b.tilt_at_last < 2.0 {
            s.push_str(&format!(
                " At {} rev/s the stone enters its last contact tilted {}° to its path: the axis has \
                 precessed about the vertical contact after contact (the lift acts behind the centre of \
                 mass, at the low edge the tilt points to, and its torque turns the direction of the \
                 tilt rather than the stone; the precession table below) until the tilt to the path \
                 was gone and the stone dived.",
                sig(b.rev_per_s, 3),
                sig(b.tilt_at_last, 2)
            ));
        }
        s.push_str(
            " This is rigid-body mechanics under the model's forces; the references report no such \
             fall (whole_throw.md §2). The one published effect added since, the air in flight \
             (§7), changes the counts but not the fall, so the count at high spin is reported as a \
             finding, not tuned.\n",
        );
    }
    s.push_str(&tilt_check_section(f));
    s
}

/// Clanet et al. (2004): the attitude holds through a contact when the stone turns at least once
/// during it (ω τ ≥ 2π). The first contact's duration τ against the spins that hold the tilt.
pub(super) fn clanet_turn_words(f: &Fidelity) -> String {
    let tau: Vec<f64> = f
        .spin
        .iter()
        .map(|r| r.first_contact_s)
        .filter(|t| t.is_finite() && *t > 0.0)
        .collect();
    if tau.is_empty() {
        return String::new();
    }
    let lo = tau.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = tau.iter().copied().fold(0.0, f64::max);
    let held: Vec<String> = f
        .spin
        .iter()
        .filter(|r| [10.0, 20.0, 40.0, 80.0, 150.0].contains(&r.rev_per_s))
        .filter(|r| r.tilt_after_first.is_finite())
        .map(|r| {
            format!(
                "{} turns per contact at {} rev/s → tilt {}°",
                sig(r.rev_per_s * r.first_contact_s, 2),
                sig(r.rev_per_s, 3),
                sig(r.tilt_after_first, 2)
            )
        })
        .collect();
    format!(
        " Clanet et al. (2004) found the attitude held through a contact when the stone turns at \
         least once during it; the first contact here lasts {}–{} ms over the sweep, so one turn \
         per contact needs {}–{} rev/s ({}; launched at 20°).",
        sig(1e3 * lo, 2),
        sig(1e3 * hi, 2),
        sig(1.0 / hi, 2),
        sig(1.0 / lo, 2),
        held.join(", ")
    )
}

/// The spin sweep at other launch tilts: median (range) per spin, against the locked count.
pub(super) fn tilt_check_section(f: &Fidelity) -> String {
    let Some((_, first)) = f.spin_tilts.first() else {
        return String::new();
    };
    let mut s = String::from(
        "\nThe same sweep launched at other tilts (median and range over the same launch heights), \
         against the attitude held at that tilt:\n\n",
    );
    let mut header = vec!["launch tilt (°)".to_owned(), "locked".to_owned()];
    header.extend(
        first
            .iter()
            .map(|r| format!("{} rev/s", sig(r.rev_per_s, 3))),
    );
    header.push("drops of the median".to_owned());
    let rows: Vec<Vec<String>> = f
        .spin_tilts
        .iter()
        .map(|(tilt, runs)| {
            let locked = locked_at(&f.locked_tilts, *tilt)
                .map_or_else(|_| "n/a".to_owned(), |l| l.skips.to_string());
            let mut row = vec![sig(*tilt, 3), locked];
            row.extend(runs.iter().map(|r| {
                let (lo, hi) = (r.members.first(), r.members.last());
                match (lo, hi) {
                    (Some(lo), Some(hi)) if lo != hi => format!("{} ({lo}–{hi})", r.median()),
                    _ => r.median().to_string(),
                }
            }));
            row.push(spin_drops(runs).to_string());
            row
        })
        .collect();
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    s.push_str(&md_table(&header, &rows));
    s
}

pub(super) fn spin_section(f: &Fidelity) -> String {
    let mut s = String::from("\n## 2. Spin\n\n![spin sweep](spin_sweep.png)\n\n");
    let rows: Vec<Vec<String>> = f
        .spin
        .iter()
        .map(|r| {
            vec![
                sig(r.rev_per_s, 3),
                r.shape.skips.to_string(),
                format!(
                    "{} ({}–{})",
                    r.median(),
                    r.members.first().unwrap_or(&0),
                    r.members.last().unwrap_or(&0)
                ),
                sig(r.shape.distance, 3),
                format!("{:.0} %", 100.0 * r.shape.final_share),
                if r.tilt_after_first.is_finite() {
                    sig(r.tilt_after_first, 3)
                } else {
                    "—".into()
                },
            ]
        })
        .collect();
    let n = f.spin.first().map_or(1, |r| r.members.len());
    let ensemble = if n > 1 {
        format!(
            "each spin is also thrown from {n} launch heights {} mm apart (±{} mm); the trend is the \
             median's",
            sig(1e3 * ensemble_step(), 2),
            sig(1e3 * ensemble_step() * (n / 2) as f64, 2),
        )
    } else {
        "the full study throws each spin from several launch heights and reads the trend from the \
         median (this quick run: the throw alone)"
            .to_string()
    };
    s.push_str(&format!(
        "The default throw (free rigid body) against spin; locked: {} skips over {} m. On the near \
         field a single run's count depends on the waves of the contacts before it, so {ensemble}.\n\n",
        f.locked.skips,
        sig(f.locked.distance, 3),
    ));
    s.push_str(&md_table(
        &[
            "spin (rev/s)",
            "skips",
            "median (range) over launch heights",
            "distance (m)",
            "last contact",
            "tilt after contact 1 (°)",
        ],
        &rows,
    ));
    s.push_str(&spin_mechanism(f));
    s.push_str(
        "\n### Precession per contact (flat water)\n\nThe angle the stone's axis turns through \
         each contact, and the change of its inclination to the vertical. A torque impulse J·ℓ turns \
         the axis by J·ℓ/(I₃ω): the turn × spin should be the same at every spin for a given \
         contact. The lever ℓ is measured: the horizontal part of the stone's change of angular \
         momentum over the contact (the water's torque impulse about the centre of mass) over the \
         water's vertical impulse m (Δv_z + g τ).\n\n",
    );
    let rows: Vec<Vec<String>> = f
        .turns
        .iter()
        .map(|t| {
            vec![
                sig(t.rev_per_s, 3),
                t.index.to_string(),
                sig(t.turn_deg, 3),
                sig(t.inclination_change_deg, 3),
                sig(t.turn_deg * t.rev_per_s, 3),
                sig(t.dvz, 3),
                sig(t.lever_mm, 3),
            ]
        })
        .collect();
    s.push_str(&md_table(
        &[
            "spin (rev/s)",
            "contact",
            "axis turn (°)",
            "inclination change (°)",
            "turn × spin",
            "Δv_z (m/s)",
            "lever ℓ (mm)",
        ],
        &rows,
    ));
    s.push_str(&curve_section(f));
    s
}

/// Touchdown at which the curve is compared across spins, and the most touchdowns charted.
pub(super) const CURVE_AT: usize = 3;
pub(super) const CURVE_TOUCHDOWNS: usize = 12;

/// The flat-water curve: its side against spin, friction's part, the mirror check.
pub struct CurveFacts {
    /// (rev/s, y at CURVE_AT with friction, without friction).
    pub by_spin: Vec<(f64, f64, f64)>,
    /// Largest |y(+ω) + y(−ω)| over the reversed pair's common touchdowns, relative to the
    /// largest |y| there.
    pub mirror: f64,
}

pub fn curve_facts(f: &Fidelity) -> CurveFacts {
    let flat = |rev: f64, friction: bool| {
        f.curve
            .iter()
            .find(|r| !r.near_field && r.friction == friction && r.rev_per_s == rev)
    };
    let by_spin = f
        .curve
        .iter()
        .filter(|r| !r.near_field && r.friction && r.rev_per_s > 0.0)
        .filter_map(|r| {
            let on = r.y_at(CURVE_AT)?;
            let off = flat(r.rev_per_s, false)?.y_at(CURVE_AT)?;
            Some((r.rev_per_s, on, off))
        })
        .collect();
    let mirror = f
        .curve
        .iter()
        .find(|r| !r.near_field && r.rev_per_s < 0.0)
        .and_then(|m| Some((m, flat(-m.rev_per_s, true)?)))
        .map_or(f64::NAN, |(m, p)| {
            let n = p.lateral.len().min(m.lateral.len());
            let scale = p.lateral[..n].iter().fold(0.0f64, |a, q| a.max(q.1.abs()));
            let worst = p
                .lateral
                .iter()
                .zip(&m.lateral)
                .fold(0.0f64, |a, (q, r)| a.max((q.1 + r.1).abs()));
            if scale > 0.0 {
                worst / scale
            } else {
                f64::NAN
            }
        });
    CurveFacts { by_spin, mirror }
}

impl CurveFacts {
    /// "+y at 40 rev/s, −y at 10 rev/s, …": the side at touchdown [`CURVE_AT`] per spin, with
    /// `unit` after each spin.
    fn sides(&self, unit: &str) -> String {
        self.by_spin
            .iter()
            .map(|b| format!("{} at {}{unit}", side(b.1), b.0))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

pub(super) fn side(y: f64) -> &'static str {
    if y > 0.0 {
        "+y"
    } else {
        "−y"
    }
}

pub(super) fn curve_section(f: &Fidelity) -> String {
    let mut s = String::from("\n### The curve\n\n![curve](curve.png)\n\n");
    s.push_str(&format!(
        "The default throw on flat water (no near field: nothing but the spin breaks the left–right \
         symmetry), spin > 0 counter-clockwise seen from above, so the leading edge moves towards \
         +y. Friction on the spinning wetted patch is the model's Magnus-like side force (the patch \
         slides sideways at ωR against the water); what is left without it is the gyroscopic part: \
         a moment turns the spinning axis sideways (a bank) — the air's pitching moment in flight \
         (§7), the lift's torque about the centre of mass in contact — and the banked lift pushes \
         sideways. Friction's part is y(on) − y(off) at touchdown {CURVE_AT}; the two parts may \
         have opposite signs.\n\n"
    ));
    let facts = curve_facts(f);
    let rows: Vec<Vec<String>> = f
        .curve
        .iter()
        .filter(|r| !r.near_field && r.friction)
        .map(|r| {
            let off = facts.by_spin.iter().find(|b| b.0 == r.rev_per_s);
            vec![
                format!("{:+}", r.rev_per_s),
                sig(r.y_at(CURVE_AT).unwrap_or(f64::NAN), 3),
                sig(r.lateral.last().map_or(f64::NAN, |p| p.1), 3),
                r.lateral.len().to_string(),
                off.map_or("n/a".into(), |b| sig(b.2, 3)),
                off.map_or("n/a".into(), |b| sig(b.1 - b.2, 3)),
            ]
        })
        .collect();
    s.push_str(&md_table(
        &[
            "spin (rev/s)",
            &format!("y at touchdown {CURVE_AT} (m)"),
            "y at the last (m)",
            "touchdowns",
            &format!("no friction: y at {CURVE_AT} (m)"),
            "friction's part (m)",
        ],
        &rows,
    ));
    s.push_str(&format!(
        "\nReversing the spin mirrors the path: over their common touchdowns |y(+ω) + y(−ω)| is at \
         most {} of the largest |y| (the mesh is mirror-symmetric; only the order of the sums \
         differs, and a run's late contacts amplify rounding, so the two may end a touchdown \
         apart). ",
        sig(facts.mirror, 2)
    ));
    s.push_str(&format!(
        "Side at touchdown {CURVE_AT}: {}. Tang et al. (2021) report a path curving towards the \
         spin, more with each bounce, with the Magnus effect dominating below ~18 rev/s; compare \
         the sides and friction's part above. The model has no Magnus side force in the air \
         (the disc model's coefficients do not depend on spin): in the air the spin \
         acts through the gyroscope, the pitching moment rolling the stone (§7), and the banked \
         lift then pushes it sideways; in the water its side force is friction on the spinning \
         patch.\n\n",
        facts.sides(" rev/s")
    ));
    let rows: Vec<Vec<String>> = f
        .curve
        .iter()
        .filter(|r| r.near_field)
        .map(|r| {
            vec![
                format!("{:+}", r.rev_per_s),
                sig(r.y_at(5).unwrap_or(f64::NAN), 3),
                sig(r.lateral.last().map_or(f64::NAN, |p| p.1), 3),
                r.lateral.len().to_string(),
            ]
        })
        .collect();
    s.push_str("On the shipped near field (wavy contact):\n\n");
    s.push_str(&md_table(
        &[
            "spin (rev/s)",
            "y at touchdown 5 (m)",
            "y at the last (m)",
            "touchdowns",
        ],
        &rows,
    ));
    s
}

pub(super) fn shape_rows<'a>(
    items: impl Iterator<Item = (String, &'a ThrowShape)>,
) -> Vec<Vec<String>> {
    items
        .map(|(label, t)| {
            vec![
                label,
                t.skips.to_string(),
                sig(t.distance, 3),
                format!("{:.0} %", 100.0 * t.final_share),
                sig(t.final_duration, 3),
                sig(t.longest_earlier_contact, 3),
                sig(t.tail_longest_hop, 3),
            ]
        })
        .collect()
}

pub(super) const SHAPE_MD: [&str; 7] = [
    "case",
    "skips",
    "distance (m)",
    "last contact",
    "last contact (s)",
    "longest earlier (s)",
    "longest tail hop (m)",
];

pub(super) fn near_section(f: &Fidelity) -> String {
    let mut s = String::from(
        "\n## 3. Planing and the near field\n\nThe default throw on a 45 × 2 m lake: on flat water, \
         and riding on the water its own pressure moves (wavy contact), for several column sizes, \
         rest depths H and ticks.\n\n",
    );
    s.push_str(&md_table(
        &SHAPE_MD,
        &shape_rows(f.near.iter().map(|n| (n.label.clone(), &n.shape))),
    ));
    s
}

pub(super) fn record_section(f: &Fidelity) -> String {
    if f.record.is_empty() {
        return "\n## 4. Record class\n\nFull runs only (crates/physics/tests/fidelity.rs checks it).\n".into();
    }
    let mut s = String::from(
        "\n## 4. Record class\n\n`record_throw.ron` (150 g, 7 mm, 30 rev/s) at 19 m/s and slower.\n\n",
    );
    s.push_str(&md_table(
        &SHAPE_MD,
        &shape_rows(
            f.record
                .iter()
                .map(|r| (format!("{} m/s", r.speed), &r.shape)),
        ),
    ));
    if let Some(r) = f.record.first() {
        s.push_str(&tail_section(r));
    }
    s
}

/// The ranges of a tail's flights and in-contact lengths, and its contacts' durations.
pub(super) fn tail_split_words(tail: &[TailHop]) -> Option<String> {
    let range = |x: &dyn Fn(&TailHop) -> f64| {
        let lo = tail.iter().map(x).fold(f64::INFINITY, f64::min);
        let hi = tail.iter().map(x).fold(f64::NEG_INFINITY, f64::max);
        (lo.is_finite() && hi.is_finite()).then_some((lo, hi))
    };
    let (f0, f1) = range(&|h| h.flight)?;
    let (c0, c1) = range(&|h| h.in_contact)?;
    let (d0, d1) = range(&|h| h.contact_s)?;
    Some(format!(
        "flights {}–{} m, in contact {}–{} m over {}–{} ms",
        sig(f0, 2),
        sig(f1, 2),
        sig(c0, 2),
        sig(c1, 2),
        sig(1e3 * d0, 2),
        sig(1e3 * d1, 2)
    ))
}

/// §4's tail: each hop of the record run's last quarter, split into contact and flight.
pub(super) fn tail_section(r: &SpeedRun) -> String {
    if r.tail.is_empty() {
        return String::new();
    }
    let mut s = format!(
        "\n### The tail\n\nThe {} m/s run's last quarter of touchdowns (grazes included, as the \
         metric counts them): a hop runs from one touchdown to the next, so it is what the stone \
         covers in contact plus its flight (the flight's duration times the exit's horizontal \
         speed).\n\n",
        r.speed
    );
    let rows: Vec<Vec<String>> = r
        .tail
        .iter()
        .map(|h| {
            vec![
                h.contact.to_string(),
                sig(h.speed_in, 3),
                sig(h.beta_in, 2),
                sig(h.tilt_in, 2),
                sig(1e3 * h.contact_s, 3),
                sig(h.exit_angle, 2),
                sig(h.hop, 2),
                sig(h.flight, 2),
                sig(h.in_contact, 2),
            ]
        })
        .collect();
    s.push_str(&md_table(
        &[
            "contact",
            "speed in (m/s)",
            "β in (°)",
            "tilt in (°)",
            "contact (ms)",
            "exit angle (°)",
            "hop (m)",
            "flight (m)",
            "in contact (m)",
        ],
        &rows,
    ));
    let over: Vec<&TailHop> = r.tail.iter().filter(|h| h.hop >= 0.5).collect();
    let flights_short = r.tail.iter().all(|h| h.flight < 0.5);
    if let Some(w) = tail_split_words(&r.tail) {
        s.push_str(&format!(
            "\n{} of {} hops are 0.5 m or longer; {w}.",
            over.len(),
            r.tail.len()
        ));
    }
    if !over.is_empty() {
        let sum = |x: &dyn Fn(&TailHop) -> f64| over.iter().map(|h| x(h)).sum::<f64>();
        let share = sum(&|h| h.in_contact) / sum(&|h| h.hop);
        s.push_str(&format!(
            " Over the hops of 0.5 m or longer the stone covers {} % of the length in contact and \
             the rest in flight{}; the criterion is not met.",
            sig(100.0 * share, 2),
            if flights_short {
                " (every flight alone is under 0.5 m)"
            } else {
                ""
            }
        ));
    }
    s.push('\n');
    s
}

pub(super) fn anchor_section(f: &Fidelity) -> String {
    let mut s = String::from(
        "\n## 5. First-bounce anchors\n\nClanet's disc at β = 20°: the smallest impact speed that \
         skips, locked (before) and as a free body at 65 rev/s with buoyancy and the smooth surface \
         (after). Measured: lowest near α = 20°, about 2.5 m/s.\n\n",
    );
    let v = |u: Option<f64>| u.map_or("no skip".to_owned(), |u| sig(u, 3));
    let rows: Vec<Vec<String>> = f
        .anchors
        .iter()
        .map(|a| {
            vec![
                sig(a.tilt_deg, 3),
                v(a.before),
                v(a.free_only),
                v(a.buoyancy_only),
                v(a.after),
            ]
        })
        .collect();
    s.push_str(&md_table(
        &[
            "α (°)",
            "U_min before (m/s)",
            "free, 65 rev/s only",
            "buoyancy only",
            "U_min after (m/s)",
        ],
        &rows,
    ));
    s
}

pub(super) fn preset_section(f: &Fidelity) -> String {
    let mut s = String::from("\n## 6. The shipped presets\n\n");
    let items = f.presets.iter().flat_map(|p| {
        [
            (format!("{} before", p.stem), &p.before),
            (format!("{} after", p.stem), &p.after),
        ]
    });
    s.push_str(&md_table(&SHAPE_MD, &shape_rows(items)));
    for p in &f.presets {
        if let Some(why) = &p.glide {
            s.push_str(&format!("\n- `{}`: {why}.", p.stem));
            if p.paper_model {
                s.push_str(
                    " The preset keeps the paper's own model, the attitude locked on flat water \
                     (issue 11 lets one shipped preset show it); that is the model that planes \
                     (§1, §3), so it fails the rule by design.",
                );
            }
        }
    }
    s.push('\n');
    s
}
