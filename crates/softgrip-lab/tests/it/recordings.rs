//! Issue 5: recordings read exactly as the spec says. The five public
//! recordings shipped in assets/recordings (and their variants) read with
//! the samples and values their files hold; malformed files give errors
//! with file and line.

use std::path::{Path, PathBuf};

use softgrip_lab::recording::{
    Marker, MarkerRef, Mode, Recording, Start, finger_marker, parse_samples,
};

fn asset(rel: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("assets/recordings")
        .join(rel)
}

#[test]
fn the_beam_recordings_read_as_time_series_of_three_markers() {
    // Window lengths from the data's README: frames 71..229, 43..269, 51..299.
    for (case, samples, last_time) in [
        ("gravity_a", 159, 1.58),
        ("load52_a", 227, 2.26),
        ("load101_a", 249, 2.48),
    ] {
        for variant in ["", "authors_frame/", "marker_centres/"] {
            let r = Recording::load(&asset(&format!("beam_ds10/{case}/{variant}recording.toml")))
                .unwrap_or_else(|e| panic!("{case} {variant}: {e}"));
            assert_eq!(r.mode, Mode::TimeSeries);
            assert_eq!(r.start, Start::Rest);
            let names: Vec<&str> = r.markers.iter().map(|m| m.name.as_str()).collect();
            assert_eq!(names, ["tip1", "tip2", "tip3"]);
            assert_eq!(r.samples.len(), samples, "{case} {variant}");
            assert_eq!(r.samples[0].time, Some(0.0));
            let t = r.samples.last().unwrap().time.unwrap();
            assert!((t - last_time).abs() < 1e-9, "{case}: last time {t}");
            for s in &r.samples {
                assert_eq!(s.load, 0.0);
                assert_eq!(s.observations.len(), 3);
                assert!(
                    s.observations
                        .iter()
                        .all(|o| o.position.iter().all(Option::is_some))
                );
            }
            assert_eq!(r.scene.object.young_modulus, 215856.0);
        }
    }
    // A value against the file: gravity_a's first row is tip1 at
    // (0.048595, 0.001025, 0.032105).
    let r = Recording::load(&asset("beam_ds10/gravity_a/recording.toml")).unwrap();
    let o = r.samples[0].observations[0];
    assert_eq!(o.marker, MarkerRef::Object(0));
    assert_eq!(o.position, [Some(0.048595), Some(0.001025), Some(0.032105)]);
    assert_eq!(o.line, 2);
}

#[test]
fn the_compression_recordings_read_as_quasi_static_plate_positions() {
    for (case, first, last) in [
        ("EF30_0T_A1", (3.89294, 0.02933668), (744.31079, 0.00999993)),
        ("EF10_0T_A1", (2.03, f64::NAN), (499.3, f64::NAN)),
    ] {
        let r = Recording::load(&asset(&format!(
            "ecoflex_compression/{case}/recording.toml"
        )))
        .unwrap_or_else(|e| panic!("{case}: {e}"));
        assert_eq!(r.mode, Mode::QuasiStatic);
        assert!(r.markers.is_empty(), "the finger is the only marker");
        assert_eq!(r.samples.len(), 30);
        for s in &r.samples {
            assert_eq!(s.time, None);
            assert_eq!(s.observations.len(), 1);
            let o = s.observations[0];
            assert_eq!(o.marker, MarkerRef::Finger(0));
            assert_eq!(o.position[0], None, "x not observed");
            assert_eq!(o.position[1], None, "y not observed");
            assert!(o.position[2].is_some());
        }
        // Loads rise monotonically along the ramp.
        assert!(r.samples.windows(2).all(|w| w[1].load > w[0].load));
        let (l0, z0) = first;
        assert!(
            (r.samples[0].load - l0).abs() < 0.01,
            "{case}: {}",
            r.samples[0].load
        );
        if z0.is_finite() {
            assert_eq!(r.samples[0].observations[0].position[2], Some(z0));
        }
        let (l1, z1) = last;
        assert!(
            (r.samples[29].load - l1).abs() < 0.1,
            "{case}: {}",
            r.samples[29].load
        );
        if z1.is_finite() {
            assert_eq!(r.samples[29].observations[0].position[2], Some(z1));
        }
    }
}

fn markers() -> Vec<Marker> {
    ["p0", "p1"]
        .iter()
        .map(|n| Marker {
            name: n.to_string(),
            reference: glam::DVec3::ZERO,
        })
        .collect()
}

#[test]
fn quasi_static_samples_follow_changes_of_load_and_never_merge_a_returning_load() {
    let csv = "time,load,marker,x,y,z,frame\n,0.0,p0,0.1,,0.2,7\n,0.0,p1,0.3,,0.4,7\n,9.73,p0,0.1,,0.19,8\n,9.73,finger,0,,0.03,8\n,0.0,p0,0.1,,0.2,9\n";
    let s = parse_samples(csv, "s.csv", Mode::QuasiStatic, &markers(), 1).expect("valid");
    assert_eq!(s.len(), 3, "load 0, 9.73, then 0 again: three samples");
    assert_eq!(s[0].observations.len(), 2);
    assert_eq!(s[1].observations[1].marker, MarkerRef::Finger(0));
    assert_eq!(s[1].observations[0].position, [Some(0.1), None, Some(0.19)]);
    assert_eq!(s[2].load, 0.0);
    // Columns by name, in any order; extra columns ignored.
    let csv = "marker,z,y,x,load,time,note\np1,3,2,1,5,,hello\n";
    let s = parse_samples(csv, "s.csv", Mode::QuasiStatic, &markers(), 0).expect("valid");
    assert_eq!(
        s[0].observations[0].position,
        [Some(1.0), Some(2.0), Some(3.0)]
    );
    assert_eq!(s[0].observations[0].marker, MarkerRef::Object(1));
}

#[test]
fn reserved_finger_names() {
    assert_eq!(finger_marker("finger"), Some(0));
    assert_eq!(finger_marker("finger1"), Some(1));
    assert_eq!(finger_marker("finger2"), Some(2));
    assert_eq!(finger_marker("finger01"), None);
    assert_eq!(finger_marker("fingertip"), None);
    assert_eq!(finger_marker("p0"), None);
}

#[test]
fn malformed_samples_name_file_and_line() {
    let m = markers();
    let cases: &[(&str, Mode, usize, &str)] = &[
        ("", Mode::QuasiStatic, 0, "s.csv:1: the file is empty"),
        (
            "time,load,marker,x,y\n",
            Mode::QuasiStatic,
            0,
            "no `z` column",
        ),
        (
            "time,load,marker,x,y,z\n,1,p9,0,0,0\n",
            Mode::QuasiStatic,
            0,
            "s.csv:2: marker \"p9\" is not in [markers] (known: p0, p1)",
        ),
        (
            "time,load,marker,x,y,z\n,1,p0,abc,0,0\n",
            Mode::QuasiStatic,
            0,
            "s.csv:2: x \"abc\" is not a number",
        ),
        (
            "time,load,marker,x,y,z\n,1,p0,nan,0,0\n",
            Mode::QuasiStatic,
            0,
            "x is nan: must be finite",
        ),
        (
            "time,load,marker,x,y,z\n,1,p0,,,\n",
            Mode::QuasiStatic,
            0,
            "no observed axis",
        ),
        (
            "time,load,marker,x,y,z\n,,p0,0,0,0\n",
            Mode::QuasiStatic,
            0,
            "load is empty",
        ),
        (
            "time,load,marker,x,y,z\n0.5,1,p0,0,0,0\n",
            Mode::QuasiStatic,
            0,
            "time is given in quasi-static mode",
        ),
        (
            "time,load,marker,x,y,z\n,1,p0,0,0,0\n",
            Mode::TimeSeries,
            0,
            "time is empty: required in time-series mode",
        ),
        (
            "time,load,marker,x,y,z\n0.2,0,p0,0,0,0\n0.1,0,p0,0,0,0\n",
            Mode::TimeSeries,
            0,
            "s.csv:3: time 0.1 s does not follow 0.2 s",
        ),
        (
            "time,load,marker,x,y,z\n0.1,0,p0,0,0,0\n0.1,0,p0,1,0,0\n",
            Mode::TimeSeries,
            0,
            "s.csv:3: marker \"p0\" appears twice in one sample (also line 2)",
        ),
        (
            "time,load,marker,x,y,z\n,1,finger,0,0,0\n",
            Mode::QuasiStatic,
            0,
            "is finger 1 but the scene has 0 finger(s)",
        ),
        (
            "time,load,marker,x,y,z\n0.1,0,p0,0,0,0\n0.1,2,p1,0,0,0\n",
            Mode::TimeSeries,
            0,
            "s.csv:3: load 2 differs",
        ),
        (
            "time,load,marker,x,y,z,time\n",
            Mode::QuasiStatic,
            0,
            "the `time` column appears twice",
        ),
        (
            "time,load,marker,x,y,z\n",
            Mode::QuasiStatic,
            0,
            "no samples after the header",
        ),
    ];
    for (csv, mode, fingers, expected) in cases {
        let e = parse_samples(csv, "s.csv", *mode, &m, *fingers)
            .expect_err(expected)
            .to_string();
        assert!(e.contains(expected), "{e:?} lacks {expected:?}");
        assert!(e.starts_with("s.csv:"), "{e}");
    }
}

#[test]
fn malformed_headers_name_the_file_and_the_key() {
    let dir = std::env::temp_dir().join(format!("softgrip-rec-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(
        asset("beam_ds10/gravity_a/scene.toml"),
        dir.join("scene.toml"),
    )
    .unwrap();
    std::fs::write(
        dir.join("samples.csv"),
        "time,load,marker,x,y,z\n0,0,p0,0,0,0\n",
    )
    .unwrap();
    let cases = [
        (
            "scene = \"scene.toml\"\nsamples = \"samples.csv\"\nmode = \"time-series\"\nspeed = 3\n[markers]\np0 = [0, 0, 0]\n",
            "line 4 `speed = 3`: unknown field `speed`",
        ),
        (
            "scene = \"scene.toml\"\nsamples = \"samples.csv\"\nmode = \"static\"\n",
            "mode = \"static\": must be",
        ),
        (
            "scene = \"scene.toml\"\nsamples = \"samples.csv\"\n",
            "mode is required",
        ),
        (
            "samples = \"samples.csv\"\nmode = \"time-series\"\n",
            "scene = \"scene.toml\" is required",
        ),
        (
            "scene = \"scene.toml\"\nsamples = \"samples.csv\"\nmode = \"quasi-static\"\nstart = \"rest\"\n",
            "start applies to mode = \"time-series\" only",
        ),
        (
            "scene = \"scene.toml\"\nsamples = \"samples.csv\"\nmode = \"time-series\"\n[markers]\np0 = [0, 0]\n",
            "[markers] p0 = [0, 0]: must be [x, y, z]",
        ),
        (
            "scene = \"missing.toml\"\nsamples = \"samples.csv\"\nmode = \"time-series\"\n",
            "missing.toml",
        ),
        (
            "scene = \"scene.toml\"\nsamples = \"none.csv\"\nmode = \"time-series\"\n[markers]\np0 = [0, 0, 0]\n",
            "none.csv",
        ),
    ];
    for (k, (text, expected)) in cases.iter().enumerate() {
        let path = dir.join(format!("r{k}.toml"));
        std::fs::write(&path, text).unwrap();
        let e = Recording::load(&path).expect_err(expected).to_string();
        assert!(e.contains(expected), "{e:?} lacks {expected:?}");
        // The header's own errors name it; a missing scene or samples
        // file names that file (in `expected`).
        if k < 6 {
            assert!(e.contains(&format!("r{k}.toml")), "{e}");
        }
    }
    let _ = std::fs::remove_dir_all(dir);
}
