//! Scenario-file forms of the irregularity and of the hunting parameters.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use tbi_track::{
    GeneratedSpec, HuntingParams, Irregularity, IrregularitySpec, RecordSpec, Spectrum,
};

#[derive(Debug, Deserialize, Serialize, PartialEq)]
struct Scenario {
    irregularity: IrregularitySpec,
    #[serde(default)]
    hunting: HuntingParams,
}

fn parse(text: &str) -> Result<Scenario, String> {
    toml::from_str(text).map_err(|e| e.to_string())
}

#[test]
fn none_generated_and_file_forms() {
    assert_eq!(
        parse("irregularity = \"none\"").unwrap().irregularity,
        IrregularitySpec::None
    );

    let s = parse(
        "irregularity = { spectrum = \"german-low\", seed = 1, lambda_min_m = 1.0, lambda_max_m = 80.0 }",
    )
    .unwrap();
    assert_eq!(
        s.irregularity,
        IrregularitySpec::Generated(GeneratedSpec::new(Spectrum::GermanLow, 1))
    );

    let s = parse(
        "[irregularity]\nspectrum = \"fra-4\"\nseed = 9\nlambda_min_m = 2\nlambda_max_m = 100\n\
         grid_spacing_m = 0.05\nmin_terms = 4000\ncontact_distance_m = 1.493\n",
    )
    .unwrap();
    assert_eq!(
        s.irregularity,
        IrregularitySpec::Generated(GeneratedSpec {
            spectrum: Spectrum::Fra(4),
            seed: 9,
            lambda_min_m: 2.0,
            lambda_max_m: 100.0,
            grid_spacing_m: 0.05,
            min_terms: 4000,
            contact_distance_m: 1.493,
        })
    );

    let s = parse("irregularity = { file = \"track.csv\" }").unwrap();
    assert_eq!(
        s.irregularity,
        IrregularitySpec::Record(RecordSpec {
            file: PathBuf::from("track.csv")
        })
    );
}

#[test]
fn serialisation_round_trips() {
    let specs = [
        IrregularitySpec::None,
        IrregularitySpec::Generated(GeneratedSpec::new(Spectrum::ChineseMainLine, 77)),
        IrregularitySpec::Record(RecordSpec {
            file: PathBuf::from("data/track.csv"),
        }),
    ];
    for irregularity in specs {
        let s = Scenario {
            irregularity,
            hunting: HuntingParams {
                amplitude_m: 2e-3,
                ..HuntingParams::default()
            },
        };
        let text = toml::to_string(&s).unwrap();
        assert_eq!(parse(&text).unwrap(), s, "{text}");
    }
}

fn err(text: &str) -> String {
    parse(text).unwrap_err()
}

#[test]
fn invalid_specs_name_the_field_and_value() {
    let e = err(
        "irregularity = { spectrum = \"german-low\", lambda_min_m = 80.0, lambda_max_m = 1.0 }",
    );
    assert!(
        e.contains("lambda_max_m = 1") && e.contains("lambda_min_m = 80"),
        "{e}"
    );

    let e = err("irregularity = { spectrum = \"german-low\", lambda_min_m = -1.0 }");
    assert!(e.contains("lambda_min_m = -1"), "{e}");

    let e = err("irregularity = { spectrum = \"german-low\", grid_spacing_m = 0.5 }");
    assert!(
        e.contains("grid_spacing_m = 0.5") && e.contains("0.25"),
        "{e}"
    );

    let e = err("irregularity = { spectrum = \"fra-2\", contact_distance_m = 0.0 }");
    assert!(e.contains("contact_distance_m = 0"), "{e}");

    let e = err("irregularity = { spectrum = \"german-medium\" }");
    assert!(e.contains("german-medium"), "{e}");
    for name in Spectrum::NAMES {
        assert!(e.contains(name), "{e} lacks {name}");
    }

    let e = err("irregularity = { spectrum = \"fra-7\" }");
    assert!(e.contains("fra-7") && e.contains("fra-6"), "{e}");

    let e = err("irregularity = { spectrum = \"german-low\", seed = -3 }");
    assert!(e.contains("seed") || e.contains("-3"), "{e}");

    let e = err("irregularity = { spectrum = \"german-low\", lamda_min_m = 1.0 }");
    assert!(e.contains("lamda_min_m"), "{e}");

    let e = err("irregularity = { spectrum = \"german-low\", file = \"a.csv\" }");
    assert!(e.contains("not both"), "{e}");

    let e = err("irregularity = { file = \"a.csv\", seed = 2 }");
    assert!(e.contains("seed") && e.contains("file"), "{e}");

    let e = err("irregularity = \"smooth\"");
    assert!(e.contains("smooth") && e.contains("none"), "{e}");

    let e = err("irregularity = {}");
    assert!(e.contains("spectrum") && e.contains("file"), "{e}");

    let e = err("irregularity = \"none\"\nhunting = { amplitude_m = 1e-3, wavelenght_m = 15.0 }");
    assert!(e.contains("wavelenght_m"), "{e}");
}

#[test]
fn spectrum_names() {
    for (name, s) in Spectrum::NAMES.iter().zip(Spectrum::ALL) {
        assert_eq!(name.parse::<Spectrum>().unwrap(), s);
        assert_eq!(s.to_string(), *name);
    }
    for alias in ["china", "Chinese", " CHINESE-MAIN-LINE "] {
        assert_eq!(
            alias.parse::<Spectrum>().unwrap(),
            Spectrum::ChineseMainLine
        );
    }
    for bad in ["fra-0", "fra-7", "fra", "german", ""] {
        let e = bad.parse::<Spectrum>().unwrap_err().to_string();
        assert!(
            e.contains("german-low") && e.contains("chinese-main-line"),
            "{e}"
        );
    }
    assert!(!Spectrum::Fra(0).is_valid() && !Spectrum::Fra(7).is_valid());
    assert!(GeneratedSpec::new(Spectrum::Fra(9), 1).validate().is_err());
}

#[test]
fn build_reads_relative_record_paths_from_the_base_dir() {
    let dir = std::env::temp_dir().join(format!("tbi-track-spec-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let sample = IrregularitySpec::Generated(GeneratedSpec::new(Spectrum::GermanHigh, 3))
        .build(0.0, 300.0, Path::new("."))
        .unwrap();
    sample.write_record_file(dir.join("track.csv")).unwrap();
    let spec = parse("irregularity = { file = \"track.csv\" }")
        .unwrap()
        .irregularity;
    let rec = spec.build(0.0, 300.0, &dir).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(matches!(rec, Irregularity::Record(_)));
    for x in [0.0, 17.31, 299.99, 1234.5] {
        assert_eq!(rec.at(x), sample.at(x));
    }
    let missing = spec
        .build(0.0, 300.0, Path::new("/nonexistent"))
        .unwrap_err()
        .to_string();
    assert!(missing.contains("/nonexistent/track.csv"), "{missing}");
    assert!(matches!(
        IrregularitySpec::None
            .build(0.0, 1.0, Path::new("."))
            .unwrap(),
        Irregularity::None
    ));
    let e = IrregularitySpec::Generated(GeneratedSpec::new(Spectrum::GermanLow, 1))
        .build(10.0, 10.0, Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(e.contains("x_end_m = 10"), "{e}");
}
