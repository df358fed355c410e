//! Params files and help as a new user meets them: tables the command does not read are
//! named (and a bad one is an error), and the README's synopses name every option that
//! each command's `--help` lists.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;
use common::{bin, extract_with_params, fails_with, repo, run, stderr, tmp};

#[test]
fn params_tables_the_command_does_not_read_are_named() {
    let o = extract_with_params(
        "other.toml",
        "[ransac]\nseed = 3\n[robot]\nwheel_base = 0.3\n",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("[ransac] is not used by extract (the algorithm is hough-split)"),
        "{err}"
    );
    assert!(
        err.contains("[robot] is not used by extract (read by simulate)"),
        "{err}"
    );
}

/// A shared params file: a typo in the table of an algorithm the run does not use is an
/// error all the same.
#[test]
fn a_bad_table_the_command_does_not_read_is_an_error() {
    for (name, toml, needle) in [
        ("bogus.toml", "[iepf]\nbogus = 1\n", "bogus"),
        ("type.toml", "[iepf]\nbreakpoints.noise = \"x\"\n", "noise"),
    ] {
        let o = extract_with_params(name, toml);
        // The file first, as every error of a params file begins.
        fails_with(&o, &[&format!("{name}: [iepf]")]);
        fails_with(
            &o,
            &["(a table extract does not use, checked all the same)"],
        );
        fails_with(&o, &[needle]);
        // `simulate` checks the tables it does not read the same way.
        let o = run(bin()
            .args(["simulate", "--maze", "2", "--duration", "1", "--params"])
            .arg(tmp(name))
            .arg("-o")
            .arg(tmp("sim-params")));
        fails_with(&o, &[&format!("{name}: [iepf]")]);
        fails_with(
            &o,
            &["(a table simulate does not use, checked all the same)"],
        );
    }
    // And the tables only `simulate` reads are checked by the other commands.
    let o = extract_with_params("robot.toml", "[robot]\nwheel_base = -1\n");
    fails_with(&o, &["robot.toml: [robot]"]);
    fails_with(
        &o,
        &["(a table extract does not use, checked all the same)"],
    );
}

/// The options a subcommand's `--help` lists (but `--help`): each as its names (`-o`,
/// `--output`).
fn options_of(command: &str) -> Vec<Vec<String>> {
    let o = run(bin().args([command, "--help"]));
    let help = String::from_utf8_lossy(&o.stdout).into_owned();
    help.lines()
        .filter_map(|l| {
            let l = l.trim_start();
            if !l.starts_with('-') {
                return None;
            }
            let names: Vec<String> = l
                .split_whitespace()
                .take_while(|w| w.starts_with('-'))
                .map(|w| w.trim_end_matches(',').to_owned())
                .collect();
            (!names.iter().any(|n| n == "--help")).then_some(names)
        })
        .collect()
}

#[test]
fn the_readme_synopses_name_every_option_of_the_help() {
    let readme = std::fs::read_to_string(repo("README.md")).unwrap();
    let section = readme
        .split("## Command line")
        .nth(1)
        .and_then(|s| s.split("```sh").nth(1))
        .and_then(|s| s.split("```").next())
        .unwrap();
    for command in [
        "extract", "render", "demo", "bench", "convert", "view", "simulate",
    ] {
        let synopsis: String = section
            .lines()
            .filter(|l| l.starts_with(&format!("laserlines {command} ")))
            .collect();
        assert!(!synopsis.is_empty(), "no synopsis of {command}");
        let options = options_of(command);
        assert!(options.len() >= 3, "{command}: {options:?}");
        for names in options {
            let named = names.iter().any(|option| {
                [" ", "]", "|"]
                    .iter()
                    .any(|end| synopsis.contains(&format!("{option}{end}")))
            });
            assert!(
                named,
                "README's synopsis of {command} lacks {names:?}: {synopsis}"
            );
        }
    }
}
