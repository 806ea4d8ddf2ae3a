//! Where relative file names are looked up: an ordered list of folders, as Mitsuba 3's file
//! resolver (`src/core/fresolver.cpp`). The rules for which folders a scene file's names see
//! are in [`crate::scene::mitsuba::resolver`].

use std::path::{Path, PathBuf};

/// An ordered list of folders to look relative file names up in.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct FileResolver {
    dirs: Vec<PathBuf>,
}

impl FileResolver {
    #[cfg(test)]
    /// A resolver searching `dirs` in order.
    pub fn new(dirs: Vec<PathBuf>) -> FileResolver {
        FileResolver { dirs }
    }

    /// The resolver a scene file starts with: its folder, then the working directory.
    pub(crate) fn for_scene(file: &Path) -> FileResolver {
        let mut dirs = vec![file.parent().map(PathBuf::from).unwrap_or_default()];
        if let Ok(cwd) = std::env::current_dir() {
            dirs.push(cwd);
        }
        FileResolver { dirs }
    }

    /// Puts `dir` first, ahead of every folder already listed.
    pub(crate) fn prepend(&mut self, dir: PathBuf) {
        self.dirs.insert(0, dir);
    }

    /// The first `dir/name` that exists; an absolute `name` if it exists; `None` otherwise.
    pub fn find(&self, name: &Path) -> Option<PathBuf> {
        if name.is_absolute() {
            return name.exists().then(|| name.to_path_buf());
        }
        self.dirs.iter().map(|d| d.join(name)).find(|p| p.exists())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_folder_holding_the_name_wins() {
        let base = std::env::temp_dir().join(format!("ophis-resolver-{}", std::process::id()));
        let (a, b) = (base.join("a"), base.join("b"));
        std::fs::create_dir_all(&a).unwrap();
        std::fs::create_dir_all(&b).unwrap();
        std::fs::write(b.join("m.ply"), "x").unwrap();
        std::fs::write(a.join("both.ply"), "x").unwrap();
        std::fs::write(b.join("both.ply"), "x").unwrap();
        let mut r = FileResolver::new(vec![b.clone()]);
        r.prepend(a.clone());
        assert_eq!(r.find(Path::new("m.ply")), Some(b.join("m.ply")));
        assert_eq!(r.find(Path::new("both.ply")), Some(a.join("both.ply")));
        assert_eq!(r.find(Path::new("none.ply")), None);
        let abs = b.join("m.ply");
        assert_eq!(r.find(&abs), Some(abs.clone()));
        let _ = std::fs::remove_dir_all(&base);
    }
}
