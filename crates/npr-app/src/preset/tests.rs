//! Tests of the parent module.

/// A bad preset is one line naming the place and what is wrong, without the excerpt
/// and caret lines of toml's own message.
#[test]
fn a_bad_preset_is_one_plain_line() {
    let text = "# mine\n\n# more\n\neffect = \"hatching-crayon\"\n";
    let Err(e) = Preset::from_toml(text, Path::new("bad.toml")) else {
        panic!("a bad effect was accepted");
    };
    let said = e.to_string();
    assert!(
        said.contains("bad.toml")
            && said.contains("line 5, column 10: unknown variant `hatching-crayon`"),
        "{said}"
    );
    assert!(
        !said.contains('|') && !said.contains('^') && !said.contains('\n'),
        "{said}"
    );
}
use super::*;

#[test]
fn round_trips_through_toml() {
    let mut p = Preset {
        effect: Effect::HatchingPencil,
        turn_deg: 12.5,
        ..Preset::default()
    };
    p.specular.edits.push(HighlightEdit {
        id: 3,
        anchor: Some([0.5, -1.0, 2.0]),
        translate: [0.1, -0.2],
        rotate_deg: 30.0,
        scale: [1.5, 0.5],
    });
    p.hatching.bins = 20;
    p.base.model = BaseModel::Cel;
    let text = p.to_toml().unwrap();
    let back = Preset::from_toml(&text, Path::new("t.toml")).unwrap();
    assert_eq!(back, p);
}

#[test]
fn every_direction_source_is_reachable_from_a_preset() {
    // The hard-edge rules are the default, the curvature-only field and the
    // paper's raw directions stay one key away.
    assert_eq!(HatchingPreset::default().direction, DirectionPreset::Smooth);
    for (key, want) in [
        ("smooth", DirectionPreset::Smooth),
        (
            "smooth-curvature-only",
            DirectionPreset::SmoothCurvatureOnly,
        ),
        ("k-max", DirectionPreset::KMax),
        ("k-min", DirectionPreset::KMin),
    ] {
        let text = format!("[hatching]\ndirection = \"{key}\"\n");
        let p = Preset::from_toml(&text, Path::new("d")).unwrap();
        assert_eq!(p.hatching.direction, want, "{key}");
    }
}

#[test]
fn partial_files_keep_defaults_and_typos_are_errors() {
    let p = Preset::from_toml("effect = \"cel\"\n[hatching]\nbins = 14\n", Path::new("a")).unwrap();
    assert_eq!(p.effect, Effect::Cel);
    assert_eq!(p.hatching.bins, 14);
    assert_eq!(p.camera, CameraPreset::default());
    let e = Preset::from_toml("[camera]\ndistanse = 2\n", Path::new("b.toml")).unwrap_err();
    assert!(e.to_string().contains("distanse"), "{e}");
    assert!(e.to_string().contains("b.toml"), "{e}");
    let e = Preset::from_toml("[specular]\nsigma = 1.5\n", Path::new("c")).unwrap_err();
    assert!(e.to_string().contains("sigma"), "{e}");
}

#[test]
fn the_example_preset_parses_and_names_every_field() {
    let path = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/presets/example.toml"
    ));
    let text = std::fs::read_to_string(path).unwrap();
    let p = Preset::from_toml(&text, path).unwrap();
    assert_eq!(p.effect, Effect::Specular);
    assert_eq!(p.specular.edits.len(), 1);
    // Every key the preset format has appears in the example (so it documents all).
    let full = Preset::default();
    let mut with_edit = full.clone();
    with_edit.specular.edits.push(HighlightEdit {
        anchor: Some([0.0; 3]),
        ..HighlightEdit::default()
    });
    let reference: toml::Table = toml::from_str(&with_edit.to_toml().unwrap()).unwrap();
    let example: toml::Table = toml::from_str(&text).unwrap();
    fn keys(t: &toml::Table, prefix: &str, out: &mut Vec<String>) {
        for (k, v) in t {
            let name = format!("{prefix}{k}");
            match v {
                toml::Value::Table(t) => keys(t, &format!("{name}."), out),
                toml::Value::Array(a) => match a.first() {
                    Some(toml::Value::Table(t)) => keys(t, &format!("{name}[]."), out),
                    _ => out.push(name),
                },
                _ => out.push(name),
            }
        }
    }
    let (mut want, mut have) = (Vec::new(), Vec::new());
    keys(&reference, "", &mut want);
    keys(&example, "", &mut have);
    for k in &want {
        assert!(have.contains(k), "example.toml lacks {k}");
    }
}

#[test]
fn effect_names_round_trip() {
    for e in Effect::ALL {
        assert_eq!(Effect::from_name(e.name()), Some(e));
    }
}

#[test]
fn the_specular_section_maps_onto_the_one_settings_type() {
    let preset = Preset::from_toml(
        "[specular]\nsigma = 0.8\nup = \"e-max\"\nsmoothing_edges = 5.0\nabstraction = 0.0\n\
         boundary = \"per-face\"\nsearch = \"gpu-frame\"\n",
        Path::new("test.toml"),
    )
    .expect("a preset");
    let s = npr_specular::SpecularSettings::from(&preset.specular);
    assert_eq!(s.tuning.controls.sigma, 0.8);
    assert_eq!(s.tuning.controls.up, npr_specular::UpAxis::KappaMax);
    assert_eq!(
        s.curvature.radius,
        npr_geometry::CurvatureRadius::EdgeLengths(5.0)
    );
    assert_eq!(s.abstraction, 0.0);
    assert_eq!(s.tuning.boundary, npr_specular::HighlightBoundary::PerFace);
    // An older preset's `search = "gpu-frame"` is the GPU backend.
    assert_eq!(s.backend, npr_specular::BackendSetting::Gpu);
    // What the preset does not set keeps the library's defaults.
    let defaults = npr_specular::HighlightTuning::default();
    assert_eq!(s.tuning.fade_frames, defaults.fade_frames);
    assert_eq!(s.tuning.max_area_change, defaults.max_area_change);
}
