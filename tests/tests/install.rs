//! The test command's qemu install step (`tests/install-qemu.sh`) in each machine
//! state it has to handle, run against a stand-in `apt-get`, `apt-cache` and
//! `dpkg-query` first on a PATH of their own: a fresh machine of the image (no
//! qemu, a newer `qemu-utils` from a backport), one with no qemu at all, one that
//! has qemu, and plans apt cannot make or that would remove or downgrade what
//! they do not name. The stand-in `apt-get install -s` prints the plan text of
//! the state (the lines are the shape of apt's own, taken from a run of the
//! real apt on such a machine) and records the arguments it was given.

use std::fs;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::Command;
use tessera_tests::firmware::repo_root;

const SEVEN: &str = "1:7.2+dfsg-7+deb12u18+b3";
const TEN: &str = "1:10.0.2+ds-2+deb13u1~bpo12+1";

/// The plan of the image's fresh machine, as `apt-get install -s` prints it with
/// the downgrade of qemu-utils asked for (the library lines shortened to two).
fn plan_fresh() -> String {
    format!(
        "NOTE: This is only a simulation!\n\
         Inst libslirp0 (4.7.0-1 Debian:12.15/oldstable [amd64])\n\
         Inst libfdt1 (1.6.1-4+b1 Debian:12.15/oldstable [amd64])\n\
         Inst qemu-utils [{TEN}] ({SEVEN} Debian:12.15/oldstable [amd64])\n\
         Inst qemu-system-common ({SEVEN} Debian:12.15/oldstable [amd64])\n\
         Inst qemu-system-data (1:7.2+dfsg-7+deb12u18 Debian:12.15/oldstable [all])\n\
         Inst qemu-system-arm ({SEVEN} Debian:12.15/oldstable [amd64])\n\
         Inst qemu-system-misc ({SEVEN} Debian:12.15/oldstable [amd64])\n\
         Conf qemu-system-arm ({SEVEN} Debian:12.15/oldstable [amd64])\n"
    )
}

/// A machine state: what dpkg has, what apt plans, who runs the script.
struct Machine {
    dir: PathBuf,
}

impl Machine {
    /// A new state in its own folder: `bin/` (the PATH: the tools the script
    /// uses, linked, and the stand-ins), `plan` and `plan_status` (what the
    /// simulation prints and its exit status), `calls` (every apt-get call).
    fn new(name: &str, plan: &str, plan_status: i32) -> Machine {
        let dir =
            std::env::temp_dir().join(format!("tessera-install-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        let bin = dir.join("bin");
        fs::create_dir_all(&bin).unwrap();
        for tool in [
            "bash", "awk", "grep", "sed", "mktemp", "tr", "paste", "rm", "cat", "dpkg", "env",
            "tail", "head", "dirname", "chmod",
        ] {
            let real = ["/usr/bin", "/bin"]
                .iter()
                .map(|d| Path::new(d).join(tool))
                .find(|p| p.exists())
                .unwrap_or_else(|| panic!("{tool} is not in /usr/bin or /bin"));
            std::os::unix::fs::symlink(real, bin.join(tool)).unwrap();
        }
        fs::write(dir.join("plan"), plan).unwrap();
        fs::write(dir.join("plan_status"), plan_status.to_string()).unwrap();
        fs::write(dir.join("calls"), "").unwrap();
        let m = Machine { dir };
        // Root, whoever runs the test (`without_root_or_sudo...` changes it).
        m.script("id", "echo 0\n");
        m.script(
            "apt-get",
            r#"d="$(dirname "$0")/.."
echo "$*" >> "$d/calls"
case "$1" in
  update) exit 0 ;;
  install) ;;
  *) exit 2 ;;
esac
for a in "$@"; do
  if [ "$a" = -s ]; then cat "$d/plan"; exit "$(cat "$d/plan_status")"; fi
done
for q in qemu-system-arm qemu-system-riscv32; do
  printf '#!/bin/sh\necho "QEMU emulator version 7.2.22"\n' > "$d/bin/$q"
  chmod +x "$d/bin/$q"
done
"#,
        );
        m.script(
            "apt-cache",
            &format!(
                r#"[ "$1" = policy ] || exit 2
printf '%s:\n  Installed: (none)\n  Candidate: {SEVEN}\n' "$2"
"#
            ),
        );
        m.script(
            "dpkg-query",
            r#"d="$(dirname "$0")/.."
for a in "$@"; do last=$a; done
[ -f "$d/installed-$last" ] || exit 1
echo "install ok installed $(cat "$d/installed-$last")"
"#,
        );
        m
    }

    /// Writes the stand-in command `name` (a bash script) into `bin/`.
    fn script(&self, name: &str, body: &str) {
        let path = self.dir.join("bin").join(name);
        fs::write(&path, format!("#!/bin/bash\n{body}")).unwrap();
        fs::set_permissions(&path, fs::Permissions::from_mode(0o755)).unwrap();
    }

    /// dpkg has `package` at `version`.
    fn has(self, package: &str, version: &str) -> Machine {
        fs::write(self.dir.join(format!("installed-{package}")), version).unwrap();
        self
    }

    /// Both emulators are on the PATH.
    fn with_qemu(self) -> Machine {
        for q in ["qemu-system-arm", "qemu-system-riscv32"] {
            self.script(q, "echo 'QEMU emulator version 7.2.22'\n");
        }
        self
    }

    /// Runs the script (with `args`): its exit status, stdout and stderr.
    fn run(&self, args: &[&str]) -> (i32, String, String) {
        let out = Command::new(self.dir.join("bin").join("bash"))
            .arg(repo_root().join("tests").join("install-qemu.sh"))
            .args(args)
            .env_clear()
            .env("PATH", self.dir.join("bin"))
            .output()
            .unwrap();
        (
            out.status.code().unwrap_or(-1),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    }

    /// The apt-get calls made, one a line.
    fn calls(&self) -> Vec<String> {
        fs::read_to_string(self.dir.join("calls"))
            .unwrap()
            .lines()
            .map(str::to_string)
            .collect()
    }

    fn has_emulators(&self) -> bool {
        self.dir.join("bin").join("qemu-system-arm").exists()
            && self.dir.join("bin").join("qemu-system-riscv32").exists()
    }
}

impl Drop for Machine {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.dir);
    }
}

fn simulations(m: &Machine) -> Vec<String> {
    m.calls()
        .into_iter()
        .filter(|c| c.starts_with("install -s"))
        .collect()
}

fn installs(m: &Machine) -> Vec<String> {
    m.calls()
        .into_iter()
        .filter(|c| c.starts_with("install") && !c.starts_with("install -s"))
        .collect()
}

/// The image's fresh machine: no qemu and qemu-utils 10 from a backport. The
/// plan pins qemu-utils to the emulators' version (without it apt removes
/// qemu-utils, or with recommends refuses), simulates, installs without
/// recommends and names the downgrade.
#[test]
fn a_fresh_machine_of_the_image_gets_qemu_with_qemu_utils_downgraded_and_named() {
    let m = Machine::new("fresh", &plan_fresh(), 0).has("qemu-utils", TEN);
    let (status, out, err) = m.run(&[]);
    assert_eq!(status, 0, "stdout:\n{out}\nstderr:\n{err}");
    let want = format!(
        "-y --no-install-recommends --allow-downgrades qemu-system-arm qemu-system-misc qemu-utils={SEVEN}"
    );
    assert_eq!(simulations(&m), [format!("install -s {want}")]);
    let inst = installs(&m);
    assert_eq!(inst.len(), 1, "{inst:?}");
    assert!(inst[0].ends_with(&want), "{inst:?}");
    assert!(m.calls()[0] == "update -qq", "{:?}", m.calls());
    assert!(
        out.contains(&format!("downgraded (1): qemu-utils {TEN} -> {SEVEN}")),
        "{out}"
    );
    assert!(
        out.contains(&format!("qemu-system-arm {SEVEN}")) && out.contains("installed (6)"),
        "{out}"
    );
    assert!(m.has_emulators());
}

/// No qemu and no qemu-utils: nothing is pinned and nothing may be downgraded.
#[test]
fn a_machine_without_qemu_utils_gets_qemu_without_downgrades() {
    let plan: String = plan_fresh()
        .lines()
        .filter(|l| !l.contains("qemu-utils"))
        .map(|l| format!("{l}\n"))
        .collect();
    let m = Machine::new("bare", &plan, 0);
    let (status, out, err) = m.run(&[]);
    assert_eq!(status, 0, "stdout:\n{out}\nstderr:\n{err}");
    assert_eq!(
        simulations(&m),
        ["install -s -y --no-install-recommends qemu-system-arm qemu-system-misc"]
    );
    assert_eq!(installs(&m).len(), 1);
    assert!(!out.contains("downgraded"), "{out}");
    assert!(m.has_emulators());
}

/// qemu present: the plan is still simulated (and refreshed lists first, as
/// root), nothing is installed.
#[test]
fn a_machine_with_qemu_checks_the_plan_and_changes_nothing() {
    let m = Machine::new("present", "NOTE: This is only a simulation!\n", 0)
        .has("qemu-utils", SEVEN)
        .with_qemu();
    let (status, out, err) = m.run(&[]);
    assert_eq!(status, 0, "stdout:\n{out}\nstderr:\n{err}");
    assert_eq!(simulations(&m).len(), 1, "{:?}", m.calls());
    assert!(installs(&m).is_empty(), "{:?}", m.calls());
    assert!(out.contains("nothing to change"), "{out}");
}

/// `--check` plans and checks on a machine without qemu, and installs nothing.
#[test]
fn check_only_installs_nothing() {
    let m = Machine::new("check", &plan_fresh(), 0).has("qemu-utils", TEN);
    let (status, out, err) = m.run(&["--check"]);
    assert_eq!(status, 0, "stdout:\n{out}\nstderr:\n{err}");
    assert!(installs(&m).is_empty(), "{:?}", m.calls());
    assert!(
        out.contains(&format!(
            "the plan would downgrade (1): qemu-utils {TEN} -> {SEVEN}"
        )),
        "{out}"
    );
    assert!(!m.has_emulators());
    let (status, _, err) = m.run(&["--install-everything"]);
    assert_eq!(status, 2);
    assert!(
        err.contains("unknown argument '--install-everything'"),
        "{err}"
    );
}

/// A plan apt cannot make fails the step even where qemu is present (the CI
/// machine), with the command to run by hand and the package apt named, not
/// apt's resolver text.
#[test]
fn a_plan_apt_cannot_make_fails_loudly_with_the_command_to_run() {
    let broken = format!(
        "Reading package lists...\n\
         Some packages could not be installed. This may mean that you have\n\
         The following packages have unmet dependencies:\n \
         qemu-utils : Breaks: qemu-system-common (< 1:8.0+dfsg-5~) but {SEVEN} is to be installed\n\
         E: Error, pkgProblemResolver::Resolve generated breaks, this may be caused by held packages.\n"
    );
    for present in [false, true] {
        let mut m = Machine::new(&format!("broken-{present}"), &broken, 100).has("qemu-utils", TEN);
        if present {
            m = m.with_qemu();
        }
        let (status, out, err) = m.run(&[]);
        assert_eq!(status, 1, "stdout:\n{out}\nstderr:\n{err}");
        assert!(installs(&m).is_empty(), "{:?}", m.calls());
        assert!(
            err.contains(
                "refused: apt cannot make the plan (qemu-utils : Breaks: qemu-system-common"
            ),
            "{err}"
        );
        assert!(
            err.contains(&format!(
                "sudo apt-get install --no-install-recommends --allow-downgrades qemu-system-arm={SEVEN}"
            )),
            "{err}"
        );
        assert!(!err.contains("pkgProblemResolver"), "{err}");
    }
}

/// A plan that removes a package, or downgrades one it does not name, is refused
/// before anything is installed.
#[test]
fn a_plan_that_removes_or_downgrades_unasked_is_refused() {
    let removes = format!(
        "Remv qemu-utils [{TEN}]\nInst qemu-system-arm ({SEVEN} Debian:12.15/oldstable [amd64])\n"
    );
    let m = Machine::new("removes", &removes, 0).has("qemu-utils", TEN);
    let (status, out, err) = m.run(&[]);
    assert_eq!(status, 1, "stdout:\n{out}\nstderr:\n{err}");
    assert!(
        err.contains(&format!("the plan removes qemu-utils {TEN}")),
        "{err}"
    );
    assert!(installs(&m).is_empty());

    let downgrades = format!(
        "Inst libslirp0 [4.8.0-1] (4.7.0-1 Debian:12.15/oldstable [amd64])\n\
         Inst qemu-system-arm ({SEVEN} Debian:12.15/oldstable [amd64])\n"
    );
    let m = Machine::new("downgrades", &downgrades, 0).has("qemu-utils", TEN);
    let (status, out, err) = m.run(&[]);
    assert_eq!(status, 1, "stdout:\n{out}\nstderr:\n{err}");
    assert!(
        err.contains("the plan downgrades libslirp0 (4.8.0-1 to 4.7.0-1), which it does not name"),
        "{err}"
    );
    assert!(installs(&m).is_empty());
}

/// Without root and without sudo, a missing qemu is not installed: the message
/// names the command to run as root.
#[test]
fn without_root_or_sudo_the_command_to_run_is_named() {
    let m = Machine::new("user", &plan_fresh(), 0).has("qemu-utils", TEN);
    m.script("id", "echo 1000\n");
    let (status, out, err) = m.run(&[]);
    assert_eq!(status, 1, "stdout:\n{out}\nstderr:\n{err}");
    assert!(installs(&m).is_empty(), "{:?}", m.calls());
    assert!(
        !m.calls().iter().any(|c| c.starts_with("update")),
        "{:?}",
        m.calls()
    );
    assert!(
        err.contains(&format!(
            "run as root:\n  apt-get install -y --no-install-recommends --allow-downgrades qemu-system-arm qemu-system-misc qemu-utils={SEVEN}"
        )),
        "{err}"
    );
}

/// Without apt-get: a missing qemu stops with what to install; a present one is
/// used with a note that the plan is not checked.
#[test]
fn without_apt_get_the_step_says_what_to_install() {
    let m = Machine::new("noapt", "", 0);
    fs::remove_file(m.dir.join("bin").join("apt-get")).unwrap();
    let (status, _, err) = m.run(&[]);
    assert_eq!(status, 1);
    assert!(err.contains("this machine has no apt-get"), "{err}");
    assert!(err.contains("install qemu 7.2"), "{err}");
    let m = m.with_qemu();
    let (status, out, _) = m.run(&[]);
    assert_eq!(status, 0);
    assert!(out.contains("the install plan is not checked"), "{out}");
}
