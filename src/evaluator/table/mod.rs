//! `table[:PATH]`: F by a baked table's f32 lookup on the CPU and its WGSL lookup on the
//! GPU. Without a path, the fabric's own table in the tables directory
//! ([`EvaluationContext::tables`]), checked to be baked from exactly the fabric's parameters;
//! with one, that file as it is (it records its fabric). A path ending in `.exr` alone is
//! read as `table:PATH`.

#[cfg(feature = "runtime")]
pub mod gpu;

use super::{
    EvaluationContext, Evaluator, EvaluatorError, EvaluatorUnit, FabricEvaluator, Parsed,
    parameter_error,
};
use crate::formats::table_exr::{TableFile, TableFileError, fabric_table_file, read_table};
use crate::measure::accuracy::{lookup_batch_f64, lookup_f32};
use crate::model::Fabric;
use crate::sampling::Sampler;
use crate::table::Table;
use glam::DVec3;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The unit's entry in the registry.
pub const UNIT: EvaluatorUnit = EvaluatorUnit {
    name: "table",
    syntax: "table[:PATH]",
    summary: "a baked table's lookup (default: TABLES/FABRIC.exr)",
    parse,
    report: None,
};

fn parse(parameter: Option<&str>) -> Parsed {
    match parameter {
        None => Ok(Arc::new(BakedTable { path: None })),
        Some("") => Err(parameter_error(&UNIT, parameter, "the path is empty")),
        Some(path) => Ok(Arc::new(BakedTable {
            path: Some(PathBuf::from(path)),
        })),
    }
}

/// A table's lookup: the file at `path`, or the fabric's table in the tables directory.
#[derive(Debug)]
pub struct BakedTable {
    pub path: Option<PathBuf>,
}

impl Evaluator for BakedTable {
    fn spelling(&self) -> String {
        match &self.path {
            None => "table".into(),
            Some(path) => format!("table:{}", path.display()),
        }
    }

    fn prepare(
        &self,
        fabric: &Fabric,
        context: &EvaluationContext,
    ) -> Result<Box<dyn FabricEvaluator>, EvaluatorError> {
        let file = match &self.path {
            Some(path) => read_table(path).map_err(TableError::File)?,
            None => load_fabric_table(&context.tables, fabric)?,
        };
        Ok(Box::new(TableEvaluation { table: file.table }))
    }
}

/// Why a fabric's table could not be used.
#[derive(Debug, thiserror::Error)]
pub enum TableError {
    #[error(
        "no table {path} for fabric '{fabric}': bake it first with `clothbake bake --fabric {fabric} --out {tables}` \
         (or `clothbake bake --scene SCENE --out {tables}`)",
        path = .path.display(),
        tables = .tables.display()
    )]
    Missing {
        path: PathBuf,
        fabric: String,
        tables: PathBuf,
    },
    #[error(
        "table {path} was baked from other parameters of '{fabric}' than the fabric file gives: \
         bake it again (`clothbake bake --fabric {fabric} --out {tables}`)",
        path = .path.display(),
        tables = .tables.display()
    )]
    Stale {
        path: PathBuf,
        fabric: String,
        tables: PathBuf,
    },
    #[error(transparent)]
    File(#[from] TableFileError),
}

impl From<TableError> for EvaluatorError {
    fn from(error: TableError) -> Self {
        EvaluatorError::Table(error)
    }
}

/// The table of `fabric` in `tables` (`NAME.exr`), checked to be baked from exactly these
/// parameters.
pub fn load_fabric_table(tables: &Path, fabric: &Fabric) -> Result<TableFile, TableError> {
    let path = tables.join(fabric_table_file(&fabric.name));
    if !path.exists() {
        return Err(TableError::Missing {
            path,
            fabric: fabric.name.clone(),
            tables: tables.to_path_buf(),
        });
    }
    let file = read_table(&path)?;
    if file.table.fabric != *fabric {
        return Err(TableError::Stale {
            path,
            fabric: fabric.name.clone(),
            tables: tables.to_path_buf(),
        });
    }
    Ok(file)
}

/// One table, read and checked (or just baked).
pub struct TableEvaluation {
    pub table: Table,
}

impl FabricEvaluator for TableEvaluation {
    fn label(&self) -> String {
        let table = &self.table;
        format!("table {} R={}", table.layout, table.resolution)
    }

    fn eval(&self, wi: DVec3, wo: DVec3) -> DVec3 {
        lookup_f32(&self.table, wi, wo)
    }

    fn eval_batch(&self, pairs: &[(DVec3, DVec3)]) -> Vec<DVec3> {
        let mut out = vec![DVec3::ZERO; pairs.len()];
        lookup_batch_f64(&self.table, pairs, &mut out);
        out
    }

    fn sampler(&self) -> Sampler {
        Sampler::for_table(&self.table)
    }

    #[cfg(feature = "runtime")]
    fn gpu(
        &self,
        context: &crate::gpu::GpuContext,
    ) -> Result<Box<dyn crate::gpu::GpuBrdf>, EvaluatorError> {
        Ok(Box::new(gpu::GpuTable::new(context, &self.table)?))
    }

    #[cfg(feature = "runtime")]
    fn gpu_wgsl(&self) -> Result<String, EvaluatorError> {
        Ok(crate::table::wgsl::lookup_wgsl(&self.table))
    }
}
