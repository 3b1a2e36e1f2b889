//! What `cargo xtask ci` needs from the system besides Rust: a Vulkan adapter for the GPU
//! tests and a C++ compiler for NVIDIA's FLIP ([`ensure_cxx`]). Where none is installed, Mesa's software driver (lavapipe) is installed with
//! apt-get, as `.ci/run` does, so the README's test command works on a fresh Debian or
//! Ubuntu machine by itself; the GPU tests are never skipped (`CI=true`). `cargo xtask farm`
//! installs Slurm the same way ([`apt_install_without_recommends`]).

use std::path::Path;
use std::process::Command;

/// Where Vulkan loaders look for installable client drivers (ICDs).
const ICD_DIRS: [&str; 3] = ["/usr/share/vulkan/icd.d", "/etc/vulkan/icd.d", "/usr/local/share/vulkan/icd.d"];

/// The Debian packages of lavapipe and the Vulkan loader.
const PACKAGES: [&str; 2] = ["mesa-vulkan-drivers", "libvulkan1"];

/// Where distributions put the Vulkan loader, for when `ldconfig` is not on `PATH`.
const LOADER_PATHS: [&str; 4] = [
    "/usr/lib/x86_64-linux-gnu/libvulkan.so.1",
    "/usr/lib/aarch64-linux-gnu/libvulkan.so.1",
    "/usr/lib64/libvulkan.so.1",
    "/usr/lib/libvulkan.so.1",
];

/// True when some Vulkan driver manifest (`*.json`) is installed in `dirs` (or
/// `VK_ICD_FILENAMES` / `VK_DRIVER_FILES` names a driver) and the loader `libvulkan.so.1` is
/// in `loader_listing` (`ldconfig -p`) or at one of [`LOADER_PATHS`].
pub fn vulkan_present(dirs: &[&Path], loader_listing: &str) -> bool {
    let named = |var: &str| std::env::var_os(var).is_some_and(|v| !v.is_empty());
    let icd = named("VK_ICD_FILENAMES")
        || named("VK_DRIVER_FILES")
        || dirs.iter().any(|d| {
            std::fs::read_dir(d)
                .is_ok_and(|entries| entries.flatten().any(|e| e.path().extension().is_some_and(|x| x == "json")))
        });
    icd && (loader_listing.contains("libvulkan.so.1") || LOADER_PATHS.iter().any(|p| Path::new(p).exists()))
}

/// `ldconfig -p`, trying `PATH` and then `/sbin` and `/usr/sbin` (not on a user's `PATH` on
/// Debian); empty when none runs.
fn ldconfig_listing() -> String {
    ["ldconfig", "/sbin/ldconfig", "/usr/sbin/ldconfig"]
        .iter()
        .find_map(|cmd| Command::new(cmd).arg("-p").output().ok().filter(|o| o.status.success()))
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default()
}

/// Installs lavapipe where no Vulkan driver is present (apt-get, through sudo when not
/// root); an error says what to install by hand where that is impossible.
pub fn ensure_vulkan() -> Result<(), String> {
    let listing = ldconfig_listing();
    let dirs: Vec<&Path> = ICD_DIRS.iter().map(Path::new).collect();
    if vulkan_present(&dirs, &listing) {
        return Ok(());
    }
    let manual = format!("install a Vulkan driver, e.g. `apt-get install -y {}`", PACKAGES.join(" "));
    eprintln!("\n==> no Vulkan driver found: installing {} (Mesa's lavapipe) for the GPU tests", PACKAGES.join(" "));
    apt_install(&PACKAGES, &manual)
}

/// Installs `g++` where no C++ compiler (`c++`, `g++` or `clang++`, or `$CXX`) is on `PATH`:
/// NVIDIA's FLIP, built by `xtask-flip` for `cargo xtask diff`, is C++.
pub fn ensure_cxx() -> Result<(), String> {
    let named = std::env::var("CXX").ok().filter(|c| !c.is_empty());
    let candidates = named.iter().map(String::as_str).chain(["c++", "g++", "clang++"]);
    if candidates.into_iter().any(|c| Command::new(c).arg("--version").output().is_ok_and(|o| o.status.success())) {
        return Ok(());
    }
    eprintln!("\n==> no C++ compiler found: installing g++ for NVIDIA's FLIP (xtask-flip)");
    apt_install(&["g++"], "install a C++ compiler, e.g. `apt-get install -y g++`")
}

/// Installs Debian packages with apt-get (through sudo when not root, without prompts); an
/// error ends with `manual`, what to do by hand where that is impossible.
pub fn apt_install(packages: &[&str], manual: &str) -> Result<(), String> {
    apt(packages, manual, &[])
}

/// [`apt_install`] without the packages' recommendations (`--no-install-recommends`).
pub fn apt_install_without_recommends(packages: &[&str], manual: &str) -> Result<(), String> {
    apt(packages, manual, &["--no-install-recommends"])
}

/// `apt-get update`, then `apt-get install -y` with `flags` and `packages`.
fn apt(packages: &[&str], manual: &str, flags: &[&str]) -> Result<(), String> {
    if Command::new("apt-get").arg("--version").output().is_err() {
        return Err(format!("no apt-get to install {}: {manual}", packages.join(" ")));
    }
    let root = Command::new("id").arg("-u").output().is_ok_and(|o| o.stdout.starts_with(b"0"));
    let prefix: Vec<&str> = if root { vec![] } else { vec!["sudo"] };
    let run = |args: &[&str]| -> Result<(), String> {
        let all: Vec<&str> = prefix.iter().copied().chain(args.iter().copied()).collect();
        let status = Command::new(all[0])
            .args(&all[1..])
            .env("DEBIAN_FRONTEND", "noninteractive")
            .status()
            .map_err(|e| format!("{}: {e}; {manual}", all.join(" ")))?;
        if status.success() { Ok(()) } else { Err(format!("`{}` failed ({status}); {manual}", all.join(" "))) }
    };
    run(&["apt-get", "update", "-qq"])?;
    let mut install = vec!["apt-get", "install", "-y", "-qq"];
    install.extend(flags);
    install.extend(packages);
    run(&install)
}

/// Prints the free space of the file system that holds the target directory (`df -h`), so a
/// CI log that ends in "No space left on device" says how much there was. Informational:
/// a machine without `df` prints nothing.
pub fn report_disk(target: &std::path::Path) {
    let dir = if target.exists() { target } else { target.parent().unwrap_or(target) };
    if let Ok(out) = Command::new("df").arg("-h").arg(dir).output()
        && out.status.success()
    {
        eprintln!("==> disk space where the build goes ({}):\n{}", dir.display(), String::from_utf8_lossy(&out.stdout));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_driver_needs_a_manifest_and_the_loader() {
        let dir = std::env::temp_dir().join(format!("xtask-icd-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let loader = "\tlibvulkan.so.1 (libc6,x86-64) => /lib/x86_64-linux-gnu/libvulkan.so.1\n";
        let dirs = [dir.as_path()];
        if std::env::var_os("VK_ICD_FILENAMES").is_none() && std::env::var_os("VK_DRIVER_FILES").is_none() {
            assert!(!vulkan_present(&dirs, loader), "an empty ICD directory is no driver");
        }
        std::fs::write(dir.join("lvp_icd.x86_64.json"), "{}").unwrap();
        assert!(vulkan_present(&dirs, loader));
        let loader_installed = LOADER_PATHS.iter().any(|p| Path::new(p).exists());
        let no_loader = "\tlibc.so.6 (libc6,x86-64) => /lib/libc.so.6\n";
        assert_eq!(vulkan_present(&dirs, no_loader), loader_installed, "the loader found by its path alone");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
