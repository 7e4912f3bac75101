//! `write_whole`: a file is replaced whole, a link at its name is replaced and what it leads
//! to is untouched, a read-only file is refused and kept, and nothing is left beside them.

use std::path::PathBuf;

use planner_maps::write_whole;

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("maps-write-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn names(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn a_file_is_written_whole_and_a_read_only_one_kept() {
    let dir = scratch("file");
    let file = dir.join("out.txt");
    write_whole(&file, b"first").unwrap();
    write_whole(&file, b"second").unwrap();
    assert_eq!(std::fs::read(&file).unwrap(), b"second");
    let mut permissions = std::fs::metadata(&file).unwrap().permissions();
    permissions.set_readonly(true);
    std::fs::set_permissions(&file, permissions).unwrap();
    let error = write_whole(&file, b"third").unwrap_err();
    assert_eq!(error.kind(), std::io::ErrorKind::PermissionDenied);
    assert_eq!(std::fs::read(&file).unwrap(), b"second");
    // A directory at the name stays a directory.
    std::fs::create_dir(dir.join("sub")).unwrap();
    assert!(write_whole(&dir.join("sub"), b"x").is_err());
    assert_eq!(names(&dir), ["out.txt", "sub"]);
}

#[cfg(unix)]
#[test]
fn a_link_is_replaced_and_its_target_untouched() {
    let dir = scratch("link");
    let target = dir.join("precious.txt");
    std::fs::write(&target, "precious").unwrap();
    std::os::unix::fs::symlink(&target, dir.join("out.txt")).unwrap();
    write_whole(&dir.join("out.txt"), b"new").unwrap();
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "precious");
    assert!(!std::fs::symlink_metadata(dir.join("out.txt"))
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(std::fs::read(dir.join("out.txt")).unwrap(), b"new");
    assert_eq!(names(&dir), ["out.txt", "precious.txt"]);
}
