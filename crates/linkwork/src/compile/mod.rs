//! Compiling: a description becomes an immutable `Model`.

use crate::error::ModelError;
use crate::input::files::ModelFile;
use crate::model::{Model, Options};

impl ModelFile {
    /// Compiles the description; an error that names an element gets its line.
    pub fn compile(&self, options: Options) -> Result<Model, ModelError> {
        Model::with_options(self.description.clone(), options).map_err(|e| self.source.locate(e))
    }
}
