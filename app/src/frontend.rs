//! Which front end made a request: the command line names an option `--seed`, the Python
//! package `seed=`. Messages about an argument name it as the user wrote it.

/// The front end a request comes from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Frontend {
    /// The `subtgraph` command line: options are `--name`.
    #[default]
    Cli,
    /// The Python package: options are keyword arguments `name=`.
    Python,
}

impl Frontend {
    /// An option as this front end spells it in messages: `--jobs` or `jobs`.
    pub fn option(self, name: &str) -> String {
        match self {
            Frontend::Cli => format!("--{name}"),
            Frontend::Python => name.replace('-', "_"),
        }
    }
}
