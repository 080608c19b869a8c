//! A misspelled scenario key or kind is refused with the closest valid name.

use tbi_tests::{run, scratch, tbi_command, text};

const SPAN: &str = r#"name = "span"
[run]
speed_kmh = 200.0
[bridge]
kind = "simply_supported"
span_m = 20.0
youngs_modulus_pa = 3.5e10
inertia_vertical_m4 = 0.9
mass_per_length_kg_m = 12000.0
[train]
kind = "hslm_a"
name = "A1"
[[probe]]
name = "mid"
x_m = 10.0
"#;

#[test]
fn a_typo_names_the_close_key() {
    let dir = scratch("suggestions");
    std::fs::create_dir_all(&dir).unwrap();
    for (from, to, want) in [
        (
            "speed_kmh = 200.0",
            "sped_kmh = 200.0",
            "did you mean `speed_kmh`?",
        ),
        ("span_m = 20.0", "span_mm = 20.0", "did you mean `span_m`?"),
        ("[[probe]]", "[[prob]]", "did you mean `probe`?"),
    ] {
        let path = dir.join("typo.toml");
        std::fs::write(&path, SPAN.replace(from, to)).unwrap();
        let r = run(tbi_command()
            .arg("run")
            .arg(&path)
            .args(["--quiet", "--out"])
            .arg(dir.join("out")));
        let err = text(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{err}");
        assert!(
            err.contains(want) && err.contains("typo.toml"),
            "{to}: {err}"
        );
    }
    // nothing close: no suggestion
    let path = dir.join("far.toml");
    std::fs::write(
        &path,
        SPAN.replace("speed_kmh = 200.0", "speed_kmh = 200.0\nxyzzy = 1"),
    )
    .unwrap();
    let r = run(tbi_command()
        .arg("run")
        .arg(&path)
        .args(["--quiet", "--out"])
        .arg(dir.join("out")));
    let err = text(&r.stderr);
    assert!(
        err.contains("unknown field `xyzzy`") && !err.contains("did you mean"),
        "{err}"
    );
}

/// A scenario path that is a FIFO is refused at once, naming it (opening a FIFO would wait
/// for a writer for ever).
#[cfg(unix)]
#[test]
fn a_fifo_scenario_is_refused_at_once() {
    let dir = scratch("fifo-scenario");
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("scenario.toml");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    assert!(made.is_ok_and(|s| s.success()), "mkfifo");
    let started = std::time::Instant::now();
    let r = run(tbi_command()
        .arg("run")
        .arg(&fifo)
        .args(["--quiet", "--out"])
        .arg(dir.join("out")));
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(
        err.contains("scenario.toml") && err.contains("a FIFO"),
        "{err}"
    );
    assert!(started.elapsed().as_secs_f64() < 10.0);
}
