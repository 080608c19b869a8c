//! Hostile and careless input: every case is refused (or ends) with a non-zero exit code and
//! a message naming the file, field or value; nothing is written outside the chosen folder;
//! no lock file and no `tbi-fmu-*` temporary folder is left behind.
//!
//! Each case runs `tbi` in its own scratch folder with its own `TMPDIR`, so the checks of
//! "nothing else written" and "no temporary folder left" look at folders only that case used.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use tbi_tests::{scratch, tbi_command, text};

/// A small scenario (one sprung mass over a 25 m span); `edit` replaces text in it.
const BASE: &str = r#"name = "case"
[run]
speed_kmh = 100.0
dt_s = 0.0005
solver = "monolithic"
free_vibration_s = 0.2
[bridge]
kind = "simply_supported"
span_m = 25.0
youngs_modulus_pa = 2.87e9
inertia_vertical_m4 = 2.9
mass_per_length_kg_m = 2303.0
modes = 5
[train]
kind = "sprung_mass"
axles = [{ offset_m = 0.0, sprung_mass_kg = 5750.0, stiffness_n_m = 1.595e6, damping_ns_m = 0.0 }]
[track]
irregularity = "none"
[[probe]]
name = "mid"
x_m = 12.5
"#;

/// A case's folder: `work/` is the working directory, `tmp/` its TMPDIR.
struct Case {
    root: PathBuf,
}

impl Case {
    fn new(label: &str) -> Case {
        let root = scratch(label);
        std::fs::create_dir_all(root.join("work")).unwrap();
        std::fs::create_dir_all(root.join("tmp")).unwrap();
        Case { root }
    }

    fn work(&self) -> PathBuf {
        self.root.join("work")
    }

    /// Write the base scenario with `(from, to)` replacements to `work/scenario.toml`.
    fn scenario(&self, edits: &[(&str, &str)]) -> PathBuf {
        let mut s = BASE.to_owned();
        for (from, to) in edits {
            assert!(s.contains(from), "{from} is not in the base scenario");
            s = s.replacen(from, to, 1);
        }
        let p = self.work().join("scenario.toml");
        std::fs::write(&p, s).unwrap();
        p
    }

    fn command(&self, args: &[&str]) -> Command {
        let mut c = tbi_command();
        c.args(args)
            .current_dir(self.work())
            .env("TMPDIR", self.root.join("tmp"));
        c
    }

    fn tbi(&self, args: &[&str]) -> Output {
        self.command(args).output().expect("tbi starts")
    }

    /// Everything below the case's root, relative, sorted.
    fn files(&self) -> Vec<String> {
        fn walk(dir: &Path, root: &Path, out: &mut Vec<String>) {
            for e in std::fs::read_dir(dir).unwrap().flatten() {
                let p = e.path();
                out.push(p.strip_prefix(root).unwrap().display().to_string());
                if p.is_dir() {
                    walk(&p, root, out);
                }
            }
        }
        let mut out = Vec::new();
        walk(&self.root, &self.root, &mut out);
        out.sort();
        out
    }

    /// Refused with exit code 1, stderr containing every `needle`, and nothing written but
    /// the scenario file (no output folder, no temporary folder).
    fn assert_refused(&self, args: &[&str], needles: &[&str]) {
        let before = self.files();
        let out = self.tbi(args);
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "tbi {args:?}: {err}");
        for n in needles {
            assert!(err.contains(n), "tbi {args:?}: expected {n:?} in: {err}");
        }
        assert_eq!(self.files(), before, "tbi {args:?} wrote files: {err}");
    }

    /// Start `tbi ARGS`, send SIGTERM once `file` (below `work/`) has `bytes` bytes, and
    /// return the exit code and standard error.
    fn interrupted(&self, args: &[&str], file: &str, bytes: u64) -> (Option<i32>, String) {
        let child = self
            .command(args)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let path = self.work().join(file);
        let t0 = std::time::Instant::now();
        while std::fs::metadata(&path).map_or(0, |m| m.len()) < bytes {
            assert!(t0.elapsed().as_secs() < 120, "the run did not start");
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        // the shell's own `kill`, so no other program is needed
        let kill = Command::new("sh")
            .args(["-c", &format!("kill -TERM {}", child.id())])
            .status()
            .unwrap();
        assert!(kill.success());
        let out = child.wait_with_output().unwrap();
        (out.status.code(), text(&out.stderr))
    }

    /// `tbi export` of `scenario` into `work/fmus`.
    fn export(&self, scenario: &Path) {
        let r = self.tbi(&["export", scenario.to_str().unwrap(), "--out", "fmus"]);
        assert!(r.status.success(), "{}", text(&r.stderr));
    }

    /// No lock file anywhere and an empty TMPDIR.
    fn assert_clean(&self) {
        let files = self.files();
        assert!(
            !files
                .iter()
                .any(|f| f.ends_with(".tbi-lock") || f.contains(".tmp-")),
            "{files:?}"
        );
        assert!(
            std::fs::read_dir(self.root.join("tmp"))
                .unwrap()
                .next()
                .is_none(),
            "temporary folders left: {files:?}"
        );
    }
}

#[test]
fn names_that_are_not_one_plain_path_component_are_refused() {
    for name in ["../../x", "..", "/tmp/abs", "a/b", ".hidden", "a\\\\b", ""] {
        let c = Case::new("name");
        let quoted = format!("name = \"{name}\"");
        let s = c.scenario(&[("name = \"case\"", &quoted)]);
        c.assert_refused(
            &["run", s.to_str().unwrap()],
            &["scenario.toml", "field `name`"],
        );
        // nothing appeared beside the case folder either
        assert!(!c.root.join("x").exists() && !c.root.parent().unwrap().join("x").exists());
    }
}

#[test]
fn out_of_range_values_are_refused_before_any_work_on_both_solvers() {
    let cases: [(&str, &str, &str); 11] = [
        ("dt_s = 0.0005", "dt_s = 1e-300", "run.dt_s"),
        ("dt_s = 0.0005", "dt_s = 1e300", "run.dt_s"),
        ("dt_s = 0.0005", "dt_s = 1e-10", "run.dt_s"),
        ("mass_per_length_kg_m = 2303.0", "mass_per_length_kg_m = 5e-324", "bridge.mass_per_length_kg_m"),
        ("mass_per_length_kg_m = 2303.0", "mass_per_length_kg_m = 1e-300", "bridge.mass_per_length_kg_m"),
        ("modes = 5", "modes = 1000000000", "bridge.modes"),
        ("free_vibration_s = 0.2", "free_vibration_s = 1e300", "run.free_vibration_s"),
        ("speed_kmh = 100.0", "speed_kmh = 1e9", "run.speed_kmh"),
        ("speed_kmh = 100.0", "speed_kmh = 100.0\nstart_x_m = 30.0", "run.start_x_m"),
        ("name = \"mid\"", "name = \"a\\nb\"", "probe[0].name"),
        (
            "kind = \"sprung_mass\"\naxles = [{ offset_m = 0.0, sprung_mass_kg = 5750.0, stiffness_n_m = 1.595e6, damping_ns_m = 0.0 }]",
            "kind = \"coach_27dof\"\nvehicles = 9223372036854775807",
            "train.vehicles",
        ),
    ];
    for (from, to, field) in cases {
        for solver in ["monolithic", "cosim"] {
            let c = Case::new("range");
            let s = c.scenario(&[(from, to)]);
            c.assert_refused(
                &[
                    "run",
                    s.to_str().unwrap(),
                    "--solver",
                    solver,
                    "--out",
                    "out",
                ],
                &["scenario.toml", field],
            );
        }
    }
}

#[test]
fn numbers_in_messages_are_short() {
    let c = Case::new("short");
    let s = c.scenario(&[("dt_s = 0.0005", "dt_s = 1e-300")]);
    let out = c.tbi(&["run", s.to_str().unwrap(), "--out", "out"]);
    let err = text(&out.stderr);
    assert!(err.contains("= 1e-300"), "{err}");
    assert!(err.len() < 400, "{err}");
    // a sweep names the speed short too, and makes no folder named by 300 digits
    let s = c.scenario(&[]);
    let out = c.tbi(&[
        "sweep",
        s.to_str().unwrap(),
        "--speeds",
        "1e-300",
        "--out",
        "sw",
    ]);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("1e-300 km/h") && err.len() < 600, "{err}");
    assert!(c.files().iter().all(|f| f.len() < 100), "{:?}", c.files());
}

#[test]
fn runs_whose_estimate_passes_the_limits_are_refused_unless_allowed() {
    // 1e-300 km/h is a positive speed, but the run would never end
    let c = Case::new("steps");
    let s = c.scenario(&[("speed_kmh = 100.0", "speed_kmh = 1e-12")]);
    c.assert_refused(
        &["run", s.to_str().unwrap(), "--out", "out"],
        &["scenario.toml", "time steps", "--allow-large"],
    );
    // 200 probes written every 1 µs step: a history.csv of tens of GB
    let c = Case::new("history");
    let probes: String = (0..200)
        .map(|i| {
            format!(
                "[[probe]]\nname = \"p{i}\"\nx_m = {}\n",
                1.0 + 0.1 * i as f64
            )
        })
        .collect();
    let s = c.scenario(&[
        ("dt_s = 0.0005", "dt_s = 0.000001"),
        ("[[probe]]\nname = \"mid\"\nx_m = 12.5\n", &probes),
    ]);
    c.assert_refused(
        &["run", s.to_str().unwrap(), "--out", "out"],
        &["scenario.toml", "history.csv would grow", "output_every"],
    );
}

#[test]
fn input_files_are_read_with_a_size_cap() {
    let c = Case::new("devzero");
    // a device is no file: refused before any byte is read
    c.assert_refused(&["run", "/dev/zero"], &["/dev/zero", "a device"]);
    // a regular file past the cap (16 MiB for a scenario; sparse, nothing written)
    let big = c.work().join("big.toml");
    std::fs::File::create(&big)
        .unwrap()
        .set_len((16 << 20) + 1)
        .unwrap();
    c.assert_refused(&["run", big.to_str().unwrap()], &["big.toml", "limit"]);
    let s = c.scenario(&[(
        "irregularity = \"none\"",
        "irregularity = { file = \"/dev/zero\" }",
    )]);
    c.assert_refused(
        &["run", s.to_str().unwrap(), "--out", "out"],
        &["track.irregularity", "a device"],
    );
    let bad = c.work().join("bad.toml");
    std::fs::write(&bad, b"name = \"a\xff\"\n").unwrap();
    c.assert_refused(
        &["run", bad.to_str().unwrap()],
        &["bad.toml", "UTF-8 at byte 9"],
    );
}

#[test]
fn an_output_folder_is_used_by_one_run_at_a_time() {
    let c = Case::new("lock");
    let s = c.scenario(&[]);
    let out = c.work().join("out");
    std::fs::create_dir_all(&out).unwrap();
    // held by a live process (this test)
    std::fs::write(out.join(".tbi-lock"), format!("{}\n", std::process::id())).unwrap();
    let r = c.tbi(&["run", s.to_str().unwrap(), "--out", "out"]);
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(
        err.contains("in use by another tbi run") && err.contains("out"),
        "{err}"
    );
    assert!(!out.join("summary.json").exists() && !out.join("history.csv").exists());
    // a lock of a process that is gone is taken over, and released at the end
    std::fs::write(out.join(".tbi-lock"), "4194399\n").unwrap();
    let r = c.tbi(&["run", s.to_str().unwrap(), "--out", "out", "--quiet"]);
    assert!(r.status.success(), "{}", text(&r.stderr));
    assert!(out.join("summary.json").is_file());
    c.assert_clean();
    // a sweep owns its whole folder: a second sweep into it is refused before any case runs
    let sweep = c.work().join("sweep");
    std::fs::create_dir_all(&sweep).unwrap();
    std::fs::write(sweep.join(".tbi-lock"), format!("{}\n", std::process::id())).unwrap();
    let args = [
        "sweep",
        s.to_str().unwrap(),
        "--speeds",
        "40,60",
        "--out",
        "sweep",
    ];
    let r = c.tbi(&args);
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(err.contains("in use by another tbi run"), "{err}");
    let entries: Vec<_> = std::fs::read_dir(&sweep).unwrap().flatten().collect();
    assert_eq!(entries.len(), 1, "only the lock: {entries:?}");
}

#[test]
fn duplicate_sweep_speeds_are_refused() {
    let c = Case::new("sweep");
    let s = c.scenario(&[]);
    c.assert_refused(
        &[
            "sweep",
            s.to_str().unwrap(),
            "--speeds",
            "70,70",
            "--out",
            "out",
        ],
        &["--speeds", "70 km/h is given twice"],
    );
}

#[test]
fn a_signal_ends_the_run_with_a_failed_summary_and_no_leftovers() {
    for solver in ["monolithic", "cosim"] {
        let c = Case::new("signal");
        // long enough to be interrupted: 0.1 ms steps over 26 s of simulated time
        let s = c.scenario(&[
            ("dt_s = 0.0005", "dt_s = 0.0001"),
            ("free_vibration_s = 0.2", "free_vibration_s = 25.0"),
        ]);
        let (code, err) = c.interrupted(
            &[
                "run",
                s.to_str().unwrap(),
                "--solver",
                solver,
                "--out",
                "out",
            ],
            "out/history.csv",
            10_000,
        );
        let history = c.work().join("out/history.csv");
        assert_eq!(code, Some(130), "{solver}: {err}");
        assert!(err.contains("interrupted by a signal"), "{solver}: {err}");
        let summary = tbi_tests::read_summary(&c.work().join("out"));
        assert_eq!(summary["status"], "failed", "{solver}");
        assert!(summary["error"].as_str().unwrap().contains("interrupted"));
        let rows = std::fs::read_to_string(&history).unwrap().lines().count();
        assert!(
            rows > 2,
            "{solver}: the rows computed so far are kept ({rows})"
        );
        c.assert_clean();
    }
}

#[test]
fn stale_temporary_folders_of_dead_processes_are_removed() {
    let c = Case::new("stale");
    let stale = c.root.join("tmp/tbi-fmu-4194399-0000abcd-0");
    std::fs::create_dir_all(stale.join("resources")).unwrap();
    let s = c.scenario(&[]);
    let r = c.tbi(&[
        "run",
        s.to_str().unwrap(),
        "--solver",
        "cosim",
        "--out",
        "out",
        "--quiet",
    ]);
    assert!(r.status.success(), "{}", text(&r.stderr));
    assert!(!stale.exists());
    c.assert_clean();
}

#[test]
fn a_truncated_shared_object_is_refused_before_dlopen() {
    let c = Case::new("elf");
    let s = c.scenario(&[]);
    c.export(&s);
    // rewrite bridge.fmu with its shared object cut in half
    let fmu = c.work().join("fmus/bridge.fmu");
    let cut = c.work().join("cut.fmu");
    tbi_tests::fmu::rewrite_zip_file(&fmu, &cut, |name, mut bytes| {
        if name.ends_with(".so") {
            bytes.truncate(bytes.len() / 2);
        }
        bytes
    });
    let r = c.tbi(&["simulate", cut.to_str().unwrap(), "--output", "out.csv"]);
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(
        err.contains("cut.fmu") && err.contains("truncated"),
        "{err}"
    );
    c.assert_clean();
}

#[test]
fn a_signal_ends_tbi_simulate_with_the_rows_so_far_kept() {
    let c = Case::new("simulate-signal");
    let s = c.scenario(&[]);
    c.export(&s);
    let (code, err) = c.interrupted(
        &[
            "simulate",
            "fmus/bridge.fmu",
            "--stop-time",
            "5",
            "--step-size",
            "1e-6",
            "--output",
            "out.csv",
            "--quiet",
        ],
        "out.csv.partial",
        100_000,
    );
    let partial = c.work().join("out.csv.partial");
    assert_eq!(code, Some(130), "{err}");
    assert!(
        err.contains("interrupted by a signal") && err.contains("out.csv.partial"),
        "{err}"
    );
    assert!(
        !c.work().join("out.csv").exists(),
        "no complete-looking result file"
    );
    let rows = std::fs::read_to_string(&partial).unwrap().lines().count();
    assert!(rows > 100, "the rows computed so far are kept ({rows})");
    c.assert_clean();
}

#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_is_reported_with_the_file_name() {
    let c = Case::new("full");
    let s = c.scenario(&[]);
    let out = c.work().join("out");
    std::fs::create_dir_all(&out).unwrap();
    // writes to /dev/full fail with ENOSPC, as on a full disk
    std::os::unix::fs::symlink("/dev/full", out.join("history.csv")).unwrap();
    let r = c.tbi(&["run", s.to_str().unwrap(), "--out", "out", "--quiet"]);
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(
        err.contains("history.csv") && err.contains("No space left on device"),
        "{err}"
    );
    c.assert_clean();
}

#[test]
fn a_negative_step_size_reaches_the_runner_check() {
    let c = Case::new("negative-step");
    let s = c.scenario(&[]);
    c.export(&s);
    let before = c.files();
    let r = c.tbi(&["simulate", "fmus/bridge.fmu", "--step-size", "-1"]);
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(
        err.contains("bridge.fmu") && err.contains("step size -1 must be a positive number"),
        "{err}"
    );
    assert_eq!(c.files(), before, "{err}");
}

#[test]
fn export_refuses_values_whose_resources_would_not_be_finite() {
    // 1e-300 kg/m gives infinite frequencies: refused by name before anything is written,
    // so no FMU that cannot instantiate is ever reported as exported
    let c = Case::new("export");
    let s = c.scenario(&[(
        "mass_per_length_kg_m = 2303.0",
        "mass_per_length_kg_m = 1e-300",
    )]);
    c.assert_refused(
        &["export", s.to_str().unwrap(), "--out", "fmus"],
        &["scenario.toml", "bridge.mass_per_length_kg_m", "1e-300"],
    );
    c.assert_clean();
}

#[test]
fn a_run_whose_plots_fail_exits_non_zero_with_a_failed_summary() {
    // a folder where the deck plot must go: the plot cannot be written
    let c = Case::new("plots");
    let s = c.scenario(&[]);
    let out = c.work().join("out");
    std::fs::create_dir_all(out.join("deck_vertical.svg").join("in-the-way")).unwrap();
    let r = c.tbi(&["run", s.to_str().unwrap(), "--out", "out", "--quiet"]);
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(err.contains("deck_vertical.svg"), "{err}");
    let summary = std::fs::read_to_string(out.join("summary.json")).expect("summary.json");
    assert!(summary.contains("\"status\": \"failed\""), "{summary}");
    assert!(summary.contains("deck_vertical.svg"), "{summary}");
    c.assert_clean();
}
