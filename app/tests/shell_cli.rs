//! `lopin completions SHELL` and `lopin man`, generated from the command line's definition:
//! every subcommand `lopin --help` lists is in each shell's completion script and has its man
//! page; the bash script parses (`bash -n`); a shell clap does not know is refused with the
//! ones it does.

use std::process::Command;

fn lopin(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_lopin"))
        .args(args)
        .output()
        .expect("lopin runs")
}

/// The subcommands `lopin --help` lists (its `Commands:` section, `help` left out).
fn subcommands() -> Vec<String> {
    let out = lopin(&["--help"]);
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    let commands = text
        .split("Commands:")
        .nth(1)
        .expect("a Commands section")
        .split("\n\n")
        .next()
        .expect("its lines");
    let names: Vec<String> = commands
        .lines()
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .filter(|n| n != "help")
        .collect();
    assert!(names.len() >= 15, "{names:?}");
    names
}

#[test]
fn completions_name_every_subcommand_in_every_shell() {
    let names = subcommands();
    let mut bash_script = Vec::new();
    for shell in ["bash", "zsh", "fish", "elvish", "powershell"] {
        let out = lopin(&["completions", shell]);
        assert!(out.status.success(), "{shell}");
        if shell == "bash" {
            bash_script.clone_from(&out.stdout);
        }
        let script = String::from_utf8_lossy(&out.stdout);
        for n in &names {
            assert!(script.contains(n.as_str()), "{shell}: no `{n}`");
        }
        // the flags of a subcommand too (fish writes them `-l param`)
        assert!(
            script.contains("param") && script.contains("resume"),
            "{shell}"
        );
    }
    let dir = std::env::temp_dir().join(format!("lopin-shell-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let bash = dir.join("lopin.bash");
    std::fs::write(&bash, &bash_script).expect("write");
    let check = Command::new("bash")
        .arg("-n")
        .arg(&bash)
        .status()
        .expect("bash");
    let _ = std::fs::remove_dir_all(&dir);
    assert!(check.success(), "the bash completion script does not parse");
    let out = lopin(&["completions", "tcsh"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("possible values: bash"),
        "{stderr}"
    );
}

#[test]
fn man_pages_cover_every_subcommand() {
    let out = lopin(&["man"]);
    assert!(out.status.success());
    let page = String::from_utf8_lossy(&out.stdout);
    assert!(
        page.contains(".TH lopin 1") && page.contains(".SH SUBCOMMANDS"),
        "{page}"
    );
    let dir = std::env::temp_dir().join(format!("lopin-man-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = lopin(&["man", "--dir", dir.to_str().expect("utf8")]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for n in subcommands() {
        let path = dir.join(format!("lopin-{n}.1"));
        let text =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(
            text.contains(&format!(".TH lopin-{n} 1")),
            "{}",
            path.display()
        );
    }
    assert!(dir.join("lopin.1").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}
