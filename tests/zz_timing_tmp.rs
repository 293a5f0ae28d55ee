use stoneskip::render::{Offscreen, SceneStyle, SimulatedScene};
fn min_ms(off: &mut Offscreen, scene: &stoneskip::render::Scene, w: u32, h: u32) -> f64 {
    let mut best = f64::MAX;
    for _ in 0..4 {
        let t = std::time::Instant::now();
        off.render(scene, w, h).unwrap();
        best = best.min(t.elapsed().as_secs_f64() * 1000.0);
    }
    best
}
#[test]
fn timing() {
    let preset = stoneskip::preset::load(std::path::Path::new("assets/presets/default.ron")).unwrap();
    let state = SimulatedScene::at_time(&preset, 0.6).unwrap();
    let scene = state.scene(SceneStyle::default());
    let mut offs = Vec::new();
    for sc in [1.0f32, 0.75, 0.5] {
        let mut off = Offscreen::with_samples(1).unwrap();
        off.renderer_mut().set_render_scale(sc);
        off.render(&scene, 1280, 720).unwrap();
        if sc == 0.5 { off.render(&scene, 1280, 720).unwrap().save("/tmp/shots/half.png").unwrap(); }
        offs.push((sc, off));
    }
    for round in 0..3 {
        let mut line = format!("round {round}:");
        for (v, off) in offs.iter_mut() {
            line += &format!("  scale {v}: {:.1}", min_ms(off, &scene, 1280, 720));
        }
        eprintln!("{line}");
    }
}
