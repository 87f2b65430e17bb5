//! Where a report goes: its directory, the plots written into it, and the
//! Markdown file that shows them.

use std::path::{Path, PathBuf};

use crate::plot::{self, PlotError};

/// Why a report could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// A file could not be written.
    #[error("cannot write the report in {path}: {source}")]
    Write {
        /// The file or directory.
        path: PathBuf,
        /// Why not.
        source: std::io::Error,
    },
    /// A plot could not be drawn.
    #[error("report plot: {0}")]
    Plot(#[from] PlotError),
}

/// The files a report wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct Written {
    /// The Markdown file.
    pub markdown: PathBuf,
    /// The plots, in the order written.
    pub images: Vec<PathBuf>,
}

pub(super) struct Out {
    dir: PathBuf,
    images: Vec<PathBuf>,
}

impl Out {
    pub(super) fn new(dir: &Path) -> Result<Out, ReportError> {
        std::fs::create_dir_all(dir).map_err(|source| ReportError::Write {
            path: dir.to_path_buf(),
            source,
        })?;
        Ok(Out {
            dir: dir.to_path_buf(),
            images: Vec::new(),
        })
    }

    /// Writes a plot and returns the Markdown that shows it.
    pub(super) fn image(
        &mut self,
        name: &str,
        png: &[u8],
        alt: &str,
    ) -> Result<String, ReportError> {
        let path = self.dir.join(name);
        plot::write_png(&path, png)?;
        self.images.push(path);
        Ok(format!("![{alt}]({name})\n\n"))
    }

    /// A chart as PNG (shown) and SVG beside it (`NAME.svg`, for print and slides).
    pub(super) fn chart(
        &mut self,
        name: &str,
        chart: &plot::Chart,
        alt: &str,
    ) -> Result<String, ReportError> {
        let md = self.image(name, &plot::chart_png(chart)?, alt)?;
        let svg_name = std::path::Path::new(name).with_extension("svg");
        write_file(&self.dir.join(&svg_name), &plot::chart_svg(chart)?)?;
        Ok(format!(
            "{} (also as [{}]({}))\n\n",
            md.trim_end(),
            svg_name.display(),
            svg_name.display()
        ))
    }

    pub(super) fn finish(self, name: &str, text: &str) -> Result<Written, ReportError> {
        let markdown = self.dir.join(name);
        write_file(&markdown, text)?;
        Ok(Written {
            markdown,
            images: self.images,
        })
    }
}

/// Writes a report's file; the error names it.
pub(super) fn write_file(path: &Path, contents: &str) -> Result<(), ReportError> {
    std::fs::write(path, contents).map_err(|source| ReportError::Write {
        path: path.to_path_buf(),
        source,
    })
}
