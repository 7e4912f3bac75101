//! `Grid` (to and from NumPy), `Problem` and `read_map`.
//!
//! Arrays are indexed `[row, column]` = `[y, x]`, the way the map files are laid out
//! (row 0 at the top), so `array.shape == (height, width)` and cell `(x, y)` is
//! `array[y, x]`.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use numpy::ndarray::Array2;
use numpy::{PyArray2, PyReadonlyArray2};
use planner_api::Cell;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::errors::{guarded, Failure};
use crate::values::Int;

/// An occupancy grid: free and blocked cells, `width` columns by `height` rows.
#[pyclass(module = "gridplan", frozen, eq)]
pub struct Grid {
    /// The grid, shared with the runs planned on it.
    pub inner: Arc<planner_api::Grid>,
    /// Where the cells lie in the ROS map frame, for a grid read from a `map_server` YAML.
    pub frame: Option<planner_maps::MapFrame>,
}

impl PartialEq for Grid {
    /// Same size, same free cells, same weights and cost rule (or both unweighted); the
    /// map frames are not compared (a grid from `to_numpy` equals its source).
    fn eq(&self, other: &Grid) -> bool {
        self.inner.width() == other.inner.width()
            && self.inner.height() == other.inner.height()
            && self.inner.free_cells() == other.inner.free_cells()
            && self.inner.weights() == other.inner.weights()
    }
}

/// `"mean"` or `"entered"` as a [`planner_api::CostRule`].
pub fn cost_rule(rule: &str, within: &str) -> Result<planner_api::CostRule, Failure> {
    match rule {
        "mean" => Ok(planner_api::CostRule::Mean),
        "entered" => Ok(planner_api::CostRule::Entered),
        other => Err(Failure::Value(format!(
            "{within}: cost_rule={other:?}; expected \"mean\" or \"entered\""
        ))),
    }
}

#[pymethods]
impl Grid {
    /// A grid from a 2-D array of shape (height, width): bools, or numbers that are all 0
    /// or 1. `free=True`: True/1 marks a free cell (seed 000's matrices); `free=False`:
    /// True/1 marks an obstacle (occupancy grids).
    #[classmethod]
    #[pyo3(signature = (array, *, free))]
    fn from_numpy(
        _cls: &Bound<'_, pyo3::types::PyType>,
        array: &Bound<'_, PyAny>,
        free: bool,
    ) -> PyResult<Grid> {
        let py = array.py();
        let numpy = py.import("numpy")?;
        let array = numpy.call_method1("asarray", (array,))?;
        let ndim: usize = array.getattr("ndim")?.extract()?;
        if ndim != 2 {
            let shape = array.getattr("shape")?;
            return Err(Failure::Value(format!(
                "Grid.from_numpy: expected a 2-D array of shape (height, width), got shape {}",
                shape.str()?
            ))
            .into());
        }
        // The size is checked before any cell is read or converted: a zero-stride view
        // (`np.broadcast_to(True, (100000, 100000))`) holds 10^10 cells in a few bytes.
        let (height, width): (u64, u64) = array.getattr("shape")?.extract()?;
        let n_cells = height.saturating_mul(width);
        if n_cells > planner_api::Grid::MAX_CELLS {
            return Err(Failure::Value(format!(
                "Grid.from_numpy: an array of shape ({height}, {width}) has {n_cells} cells, more than a grid's limit of {}",
                planner_api::Grid::MAX_CELLS
            ))
            .into());
        }
        // At most 2^31 cells, so this fits a usize on any platform with 64-bit pointers and
        // is refused as too large elsewhere.
        let n_cells = usize::try_from(n_cells).map_err(|_| {
            Failure::Value(format!(
                "Grid.from_numpy: an array of shape ({height}, {width}) is too large"
            ))
        })?;
        // One byte a cell, reserved fallibly: MemoryError, not an abort, when it cannot be had.
        let mut cells: Vec<bool> = Vec::new();
        cells.try_reserve_exact(n_cells).map_err(|_| {
            pyo3::exceptions::PyMemoryError::new_err(format!(
                "Grid.from_numpy: no memory for the {n_cells} cells of a {width}x{height} grid"
            ))
        })?;
        let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
        match kind.as_str() {
            "b" => {
                let view: PyReadonlyArray2<'_, bool> = array.extract()?;
                cells.extend(view.as_array().iter().map(|&marked| marked == free));
            }
            "i" | "u" | "f" => {
                let converted = array.call_method1("astype", ("float64",))?;
                let view: PyReadonlyArray2<'_, f64> = converted.extract()?;
                let values = view.as_array();
                if let Some(((y, x), value)) = values
                    .indexed_iter()
                    .find(|(_, v)| **v != 0.0 && **v != 1.0)
                {
                    return Err(Failure::Value(format!(
                        "Grid.from_numpy: cell ({x}, {y}) (array[{y}, {x}]) is {value}, expected 0 or 1"
                    ))
                    .into());
                }
                cells.extend(values.iter().map(|v| (*v == 1.0) == free));
            }
            _ => {
                return Err(Failure::Type(format!(
                    "Grid.from_numpy: expected a bool or 0/1 numeric array, got dtype {}",
                    array.getattr("dtype")?.str()?
                ))
                .into())
            }
        }
        let (Ok(width), Ok(height)) = (u32::try_from(width), u32::try_from(height)) else {
            return Err(Failure::Value(format!(
                "Grid.from_numpy: an array of shape ({height}, {width}) is too large"
            ))
            .into());
        };
        let grid = planner_api::Grid::from_free_cells(width, height, cells)
            .map_err(|e| Failure::Value(format!("Grid.from_numpy: {e}")))?;
        Ok(Grid {
            inner: Arc::new(grid),
            frame: None,
        })
    }

    /// This grid with a weight per cell from a 2-D integer array of the grid's shape
    /// (height, width), every value from 1 to 65535 (blocked cells too; they stay
    /// blocked), and the move cost rule: `"mean"` (length times the mean of the two cells'
    /// weights, the default) or `"entered"` (times the entered cell's weight).
    #[pyo3(signature = (weights, *, cost_rule = "mean"))]
    fn with_weights(&self, weights: &Bound<'_, PyAny>, cost_rule: &str) -> PyResult<Grid> {
        let within = "Grid.with_weights";
        let rule = self::cost_rule(cost_rule, within)?;
        let py = weights.py();
        let array = py.import("numpy")?.call_method1("asarray", (weights,))?;
        let shape: Vec<u64> = array.getattr("shape")?.extract()?;
        let (width, height) = (self.inner.width(), self.inner.height());
        if shape != [u64::from(height), u64::from(width)] {
            return Err(Failure::Value(format!(
                "{within}: expected an array of the grid's shape ({height}, {width}), got shape {}",
                array.getattr("shape")?.str()?
            ))
            .into());
        }
        let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
        if kind != "i" && kind != "u" {
            return Err(Failure::Type(format!(
                "{within}: expected an integer array (weights are integers from 1 to 65535), got dtype {}",
                array.getattr("dtype")?.str()?
            ))
            .into());
        }
        // Unsigned arrays are read as u64, so that a value beyond i64 is named as itself.
        let (cells, bad) = if kind == "u" {
            let converted = array.call_method1("astype", ("uint64",))?;
            let view: PyReadonlyArray2<'_, u64> = converted.extract()?;
            weight_cells(view.as_array())
        } else {
            let converted = array.call_method1("astype", ("int64",))?;
            let view: PyReadonlyArray2<'_, i64> = converted.extract()?;
            weight_cells(view.as_array())
        };
        if let Some(((y, x), value)) = bad {
            return Err(Failure::Value(format!(
                "{within}: cell ({x}, {y}) (array[{y}, {x}]) has weight {value}; weights are integers from 1 to 65535"
            ))
            .into());
        }
        let grid = (*self.inner)
            .clone()
            .with_weights(cells, rule)
            .map_err(|e| Failure::Value(format!("{within}: {e}")))?;
        Ok(Grid {
            inner: Arc::new(grid),
            frame: self.frame,
        })
    }

    /// Where the cells lie in the ROS map frame ([`MapFrame`]): a grid read from a
    /// `map_server` `.yaml` has its resolution and origin; None for other grids.
    #[getter]
    fn frame(&self) -> Option<MapFrame> {
        self.frame.map(|inner| MapFrame { inner })
    }

    /// The cell weights as a uint16 array of shape (height, width), or None on an
    /// unweighted grid.
    #[getter]
    fn weights<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<u16>>> {
        let grid = &self.inner;
        let weights = grid.weights()?.cells();
        let width = grid.width() as usize;
        let array = Array2::from_shape_fn((grid.height() as usize, width), |(y, x)| {
            weights[y * width + x]
        });
        Some(PyArray2::from_owned_array(py, array))
    }

    /// The move cost rule of a weighted grid (`"mean"` or `"entered"`), else None.
    #[getter]
    fn cost_rule(&self) -> Option<&'static str> {
        self.inner.weights().map(|w| w.rule().name())
    }

    /// The grid as a bool array of shape (height, width). `free=True` (the default): True
    /// marks free cells; `free=False`: True marks obstacles.
    #[pyo3(signature = (*, free = true))]
    fn to_numpy<'py>(&self, py: Python<'py>, free: bool) -> Bound<'py, PyArray2<bool>> {
        let grid = &self.inner;
        let array =
            Array2::from_shape_fn((grid.height() as usize, grid.width() as usize), |(y, x)| {
                grid.is_free(Cell::new(x as u32, y as u32)) == free
            });
        PyArray2::from_owned_array(py, array)
    }

    /// Columns.
    #[getter]
    fn width(&self) -> u32 {
        self.inner.width()
    }

    /// Rows.
    #[getter]
    fn height(&self) -> u32 {
        self.inner.height()
    }

    /// `(height, width)`, the shape of `to_numpy()`.
    #[getter]
    fn shape(&self) -> (u32, u32) {
        (self.inner.height(), self.inner.width())
    }

    /// The number of free cells.
    #[getter]
    fn n_free(&self) -> usize {
        self.inner.n_free()
    }

    /// Whether cell `(x, y)` lies on the grid and is free.
    fn is_free(&self, cell: &Bound<'_, PyAny>) -> PyResult<bool> {
        Ok(match given_cell("Grid.is_free", cell)? {
            GivenCell::At(x, y) => match to_cell((x, y)) {
                Some(c) => self.inner.contains(c) && self.inner.is_free(c),
                None => false,
            },
            GivenCell::Beyond(..) => false,
        })
    }

    /// Pickling (and `copy`): the free cells, the weights and their rule, the frame.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let py = slf.py();
        let grid = slf.get();
        let state = (
            grid.to_numpy(py, true),
            grid.weights(py),
            grid.cost_rule(),
            grid.frame(),
        );
        Ok((
            slf.get_type().getattr("_from_state")?,
            state.into_pyobject(py)?,
        ))
    }

    /// The grid `__reduce__` describes.
    #[classmethod]
    #[pyo3(name = "_from_state")]
    fn from_state(
        cls: &Bound<'_, pyo3::types::PyType>,
        free: &Bound<'_, PyAny>,
        weights: Option<&Bound<'_, PyAny>>,
        cost_rule: Option<&str>,
        frame: Option<&Bound<'_, MapFrame>>,
    ) -> PyResult<Grid> {
        let mut grid = Grid::from_numpy(cls, free, true)?;
        if let Some(weights) = weights {
            grid = grid.with_weights(weights, cost_rule.unwrap_or("mean"))?;
        }
        grid.frame = frame.map(|f| f.get().inner);
        Ok(grid)
    }

    fn __repr__(&self) -> String {
        let weighted = match self.inner.weights() {
            Some(w) => format!(
                ", weights {}-{} ({} rule)",
                w.min(),
                w.max(),
                w.rule().name()
            ),
            None => String::new(),
        };
        format!(
            "Grid(width={}, height={}, n_free={}{weighted})",
            self.inner.width(),
            self.inner.height(),
            self.inner.n_free()
        )
    }
}

/// `(x, y)` as a cell, if both fit.
pub fn to_cell((x, y): (i64, i64)) -> Option<Cell> {
    Some(Cell::new(u32::try_from(x).ok()?, u32::try_from(y).ok()?))
}

/// A cell argument as given.
pub enum GivenCell<'py> {
    /// `(x, y)`.
    At(i64, i64),
    /// Integers `(x, y)`, one of them beyond `i64`: a cell on no grid.
    Beyond(Bound<'py, PyAny>, Bound<'py, PyAny>),
}

/// Cell argument `name`: any sequence of two integers (a tuple, a list, a NumPy array, NumPy
/// integers), else a `TypeError` naming the argument.
pub fn given_cell<'py>(name: &str, value: &Bound<'py, PyAny>) -> PyResult<GivenCell<'py>> {
    // The usual tuple of two ints, without going through Python.
    if let Ok((x, y)) = value.extract::<(i64, i64)>() {
        return Ok(GivenCell::At(x, y));
    }
    let wrong = || -> PyErr {
        let shown = value
            .repr()
            .map(|r| r.to_string())
            .unwrap_or_else(|_| "a value".into());
        let shown = match shown.char_indices().nth(80) {
            Some((end, _)) => format!("{}...", &shown[..end]),
            None => shown,
        };
        Failure::Type(format!(
            "{name}: expected a cell (x, y), two integers, got {shown}"
        ))
        .into()
    };
    let text = value.is_instance_of::<pyo3::types::PyString>()
        || value.is_instance_of::<pyo3::types::PyBytes>();
    if text || value.len().ok() != Some(2) {
        return Err(wrong());
    }
    let operator = value.py().import("operator")?;
    // `operator.index`: an int, a NumPy integer, or anything else that is an integer.
    let coordinate = |i: usize| {
        value
            .get_item(i)
            .and_then(|item| operator.call_method1("index", (item,)))
            .map_err(|_| wrong())
    };
    let (x, y) = (coordinate(0)?, coordinate(1)?);
    match (x.extract::<i64>(), y.extract::<i64>()) {
        (Ok(x), Ok(y)) => Ok(GivenCell::At(x, y)),
        _ => Ok(GivenCell::Beyond(x, y)),
    }
}

/// Endpoint `name` (`start` or `goal`) of a query on `grid`, as [`given_cell`] takes it:
/// one beyond `i64` is the `ProblemError` of a cell outside the grid.
pub fn endpoint(
    name: &'static str,
    value: &Bound<'_, PyAny>,
    grid: &planner_api::Grid,
) -> PyResult<(i64, i64)> {
    match given_cell(name, value)? {
        GivenCell::At(x, y) => Ok((x, y)),
        GivenCell::Beyond(x, y) => {
            let message = crate::plan::outside(name, &x, &y, grid);
            let cell = (x, y).into_pyobject(value.py())?.into_any();
            Err(crate::errors::problem_pyerr(
                value.py(),
                name,
                cell,
                message,
            ))
        }
    }
}

/// A start-goal problem a map file states: its own pairs (seed 003's `.txt` header), or a
/// Moving AI `.scen` file's beside a `.map`.
#[pyclass(module = "gridplan", name = "Problem", frozen, eq, get_all)]
#[derive(Clone, PartialEq)]
pub struct MapProblem {
    /// `(x, y)` of the start.
    pub start: (u32, u32),
    /// `(x, y)` of the goal.
    pub goal: (u32, u32),
    /// The optimal length the scenario file states, if any.
    pub optimal_length: Option<f64>,
    /// The scenario file's bucket, if any.
    pub bucket: Option<u32>,
}

#[pymethods]
impl MapProblem {
    /// Pickling (and `copy`): its fields.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let p = slf.get();
        let state = (p.start, p.goal, p.optimal_length, p.bucket);
        Ok((
            slf.get_type().getattr("_from_state")?,
            state.into_pyobject(slf.py())?,
        ))
    }

    /// The problem `__reduce__` describes.
    #[classmethod]
    #[pyo3(name = "_from_state")]
    fn from_state(
        _cls: &Bound<'_, pyo3::types::PyType>,
        start: (u32, u32),
        goal: (u32, u32),
        optimal_length: Option<f64>,
        bucket: Option<u32>,
    ) -> MapProblem {
        MapProblem {
            start,
            goal,
            optimal_length,
            bucket,
        }
    }

    fn __repr__(&self) -> String {
        let mut text = format!("Problem(start={:?}, goal={:?}", self.start, self.goal);
        if let Some(length) = self.optimal_length {
            text.push_str(&format!(", optimal_length={length}"));
        }
        if let Some(bucket) = self.bucket {
            text.push_str(&format!(", bucket={bucket}"));
        }
        text + ")"
    }
}

/// Reads a map file of any format the command line reads (`.map`, `.txt`, `.csv`, ROS
/// `.yaml`) and returns `(grid, problems)`: the file's own start-goal pairs, else those of
/// the `.scen` file beside a `.map` (as `plan` uses them), else none. `obstacle` is the
/// value that marks an obstacle in a `.csv` matrix (0, seed 000's default, or 1), as
/// `plan --obstacle` takes it. `weights`: a weight `.csv` for the map (`plan --weights`);
/// `graded=True`: a ROS map's graded values as costs with nav2's bands (`plan --graded`);
/// `lethal` and `unknown`: those bands' lethal cost and the cost of unknown cells
/// (`plan --lethal`, `--unknown`; each implies `graded`); `swamp` and `water`: Moving AI
/// terrain weights (`plan --swamp`, `--water`); `cost_rule`: the move cost rule of the
/// weighted grid (`plan --cost-rule`). The options are checked as the command line checks
/// its flags: one that would change nothing, or two that contradict each other, raise
/// `ValueError` naming the argument.
#[pyfunction]
#[pyo3(
    signature = (path, *, obstacle = Int::Fits(0), weights = None, graded = false, lethal = None, unknown = None, swamp = None, water = None, cost_rule = "mean"),
    text_signature = "(path, *, obstacle=0, weights=None, graded=False, lethal=None, unknown=None, swamp=None, water=None, cost_rule='mean')"
)]
#[allow(clippy::too_many_arguments)]
pub fn read_map(
    py: Python<'_>,
    path: PathBuf,
    obstacle: Int,
    weights: Option<PathBuf>,
    graded: bool,
    lethal: Option<Int>,
    unknown: Option<Int>,
    swamp: Option<Int>,
    water: Option<Int>,
    cost_rule: &str,
) -> PyResult<Py<PyTuple>> {
    let csv = match &obstacle {
        Int::Fits(n) => u8::try_from(*n)
            .ok()
            .and_then(planner_maps::CsvConvention::from_obstacle_value),
        Int::Beyond { .. } => None,
    };
    let csv = csv.ok_or_else(|| {
        Failure::Value(format!(
            "read_map: obstacle={obstacle}; the obstacle value of a .csv matrix is 0 or 1"
        ))
    })?;
    let obstacle = csv.obstacle_value();
    let format = planner_maps::MapFormat::from_path(&path);
    // As `plan --obstacle`: the obstacle value is a `.csv` matrix's, and is refused for
    // another map rather than ignored.
    if obstacle != 0 && !matches!(format, Ok(planner_maps::MapFormat::Matrix)) {
        return Err(Failure::Value(format!(
            "read_map: obstacle={obstacle} applies to .csv maps, not {}",
            path.display()
        ))
        .into());
    }
    let given = CostArgs {
        weights: weights.is_some(),
        graded,
        lethal,
        unknown,
        swamp,
        water,
        cost_rule,
    };
    let options = planner_maps::ReadOptions {
        csv,
        costs: cost_options(&path, format.ok(), &given)?,
        ..planner_maps::ReadOptions::default()
    };
    let call = crate::warn::Call::begin();
    let read = py.detach(|| {
        guarded(|| {
            let (grid, frame, problems) = read(&path, &options)?;
            let grid = match &weights {
                Some(file) => planner_maps::read_weights(file, grid, options.costs.rule, &options)?,
                None => grid,
            };
            Ok((grid, frame, problems))
        })
    });
    // What the readers doubted (a ROS map's ignored keys, a scenario of another map).
    let (grid, frame, problems) = call.end(py, read.map_err(PyErr::from))?;
    let grid = Py::new(
        py,
        Grid {
            inner: Arc::new(grid),
            frame,
        },
    )?;
    let problems: Vec<Py<MapProblem>> = problems
        .into_iter()
        .map(|p| Py::new(py, p))
        .collect::<PyResult<_>>()?;
    Ok((grid, problems).into_pyobject(py)?.unbind())
}

/// `read_map`'s cost arguments, as given.
struct CostArgs<'a> {
    /// Whether a weight file was given.
    weights: bool,
    graded: bool,
    lethal: Option<Int>,
    unknown: Option<Int>,
    swamp: Option<Int>,
    water: Option<Int>,
    cost_rule: &'a str,
}

/// `value` of argument `name` if it lies from `min` to `max`, else the `ValueError` that
/// says `what` the argument takes.
fn in_range(name: &str, value: &Int, min: u16, max: u16, what: &str) -> Result<u16, Failure> {
    match value {
        Int::Fits(n) if (i64::from(min)..=i64::from(max)).contains(n) => Ok(*n as u16),
        _ => Err(Failure::Value(format!("read_map: {name}={value}; {what}"))),
    }
}

/// The cost options of `read_map`'s arguments for the map at `path`, checked as
/// `gridplan plan` checks `--weights`, `--graded`, `--lethal`, `--unknown`, `--swamp`,
/// `--water` and `--cost-rule` (planner-runner's `PlanCosts`): an option that would change
/// nothing, or two that contradict each other, raise `ValueError` naming the argument.
/// `lethal` and `unknown` imply `graded`; graded costs are a ROS map's, terrain weights a
/// Moving AI map's, and a weight file gives every cell's weight, so it goes with neither.
fn cost_options(
    path: &Path,
    format: Option<planner_maps::MapFormat>,
    given: &CostArgs<'_>,
) -> Result<planner_maps::CostOptions, Failure> {
    use planner_maps::MapFormat;
    let mut options = planner_maps::CostOptions {
        rule: self::cost_rule(given.cost_rule, "read_map")?,
        ..planner_maps::CostOptions::default()
    };
    let graded = given.graded || given.lethal.is_some() || given.unknown.is_some();
    let terrain = given.swamp.is_some() || given.water.is_some();
    if given.weights && (graded || terrain) {
        return Err(Failure::Value(
            "read_map: weights gives every cell's weight; it does not go with graded=True, \
             lethal, unknown, swamp or water"
                .into(),
        ));
    }
    if graded {
        if !matches!(format, Some(MapFormat::Ros | MapFormat::Image)) {
            let what = match (&given.lethal, &given.unknown) {
                _ if given.graded => "graded=True".to_string(),
                (Some(lethal), _) => format!("lethal={lethal}"),
                (None, Some(unknown)) => format!("unknown={unknown}"),
                (None, None) => "graded=True".to_string(),
            };
            return Err(Failure::Value(format!(
                "read_map: {what} applies to ROS maps (.yaml, .pgm, .png), not {}",
                path.display()
            )));
        }
        options.graded = true;
        if let Some(lethal) = &given.lethal {
            if matches!(lethal, Int::Fits(0)) {
                return Err(Failure::Value(
                    "read_map: lethal=0 would block every cell; costs from lethal up are \
                     blocked (254 is nav2's LETHAL_OBSTACLE; its planners block from 253, \
                     INSCRIBED, for the robot's centre)"
                        .into(),
                ));
            }
            options.bands.lethal = in_range(
                "lethal",
                lethal,
                1,
                255,
                "the lethal cost is a costmap cost, from 1 to 255 (nav2's LETHAL_OBSTACLE: 254)",
            )? as u8;
        }
        if let Some(unknown) = &given.unknown {
            let what = "the cost of an unknown cell is from 0 to 254 (leave it out to block \
                        unknown cells)";
            options.bands.unknown = Some(in_range("unknown", unknown, 0, 254, what)? as u8);
        }
    }
    if terrain {
        if !matches!(format, Some(MapFormat::MovingAi)) {
            return Err(Failure::Value(format!(
                "read_map: swamp and water weigh Moving AI terrain (.map files), not {}",
                path.display()
            )));
        }
        let Some(swamp) = &given.swamp else {
            return Err(Failure::Value(
                "read_map: water needs swamp (the weight of swamp `S`)".into(),
            ));
        };
        let what = "swamp and water are weights, from 1 to 65535";
        options.terrain = Some(planner_maps::TerrainWeights {
            swamp: in_range("swamp", swamp, 1, u16::MAX, what)?,
            water: given
                .water
                .as_ref()
                .map(|water| in_range("water", water, 1, u16::MAX, what))
                .transpose()?,
        });
    }
    if given.cost_rule != "mean" && !given.weights && !graded && !terrain {
        return Err(Failure::Value(format!(
            "read_map: cost_rule={:?} needs costs to apply to: weights, graded=True, lethal, \
             unknown or swamp",
            given.cost_rule
        )));
    }
    Ok(options)
}

fn read(
    path: &Path,
    options: &planner_maps::ReadOptions,
) -> Result<
    (
        planner_api::Grid,
        Option<planner_maps::MapFrame>,
        Vec<MapProblem>,
    ),
    Failure,
> {
    let file = planner_runner::config::read_map_file(path, options)?;
    let mut problems: Vec<MapProblem> = file
        .problems
        .iter()
        .map(|p| MapProblem {
            start: (p.start.x, p.start.y),
            goal: (p.goal.x, p.goal.y),
            optimal_length: None,
            bucket: None,
        })
        .collect();
    let scen = PathBuf::from(format!("{}.scen", path.display()));
    if problems.is_empty() && scen.is_file() {
        // As `gridplan plan` reads them (planner-runner's `own_pairs`): scenarios that name
        // another map file are read, with one warning.
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        let mut warned = false;
        for s in planner_maps::read_scenarios(&scen)? {
            if (s.width, s.height) != (file.grid.width(), file.grid.height()) {
                return Err(Failure::MapMismatch {
                    file: scen.display().to_string(),
                    line: s.line,
                    message: format!(
                        "{}:{}: the scenario is for a {}x{} map, but {} is {}x{}",
                        scen.display(),
                        s.line,
                        s.width,
                        s.height,
                        path.display(),
                        file.grid.width(),
                        file.grid.height()
                    ),
                });
            }
            if !warned && !s.names_map(&name) {
                tracing::warn!(
                    "{}:{}: the scenario names map {}, not {}",
                    scen.display(),
                    s.line,
                    s.map,
                    name
                );
                warned = true;
            }
            problems.push(MapProblem {
                start: (s.start.x, s.start.y),
                goal: (s.goal.x, s.goal.y),
                optimal_length: Some(s.optimal_length),
                bucket: Some(s.bucket),
            });
        }
    }
    Ok((file.grid, file.frame, problems))
}

/// The first weight out of 1..=65535: its `(row, column)` and its value as written.
type OutOfRange = Option<((usize, usize), String)>;

/// The weights of `values` as cells, with the first value out of range, if any.
fn weight_cells<T>(values: numpy::ndarray::ArrayView2<'_, T>) -> (Vec<u16>, OutOfRange)
where
    T: Copy + std::fmt::Display + TryInto<u16>,
{
    let weight = |v: T| v.try_into().ok().filter(|&w: &u16| w >= 1);
    let bad = values
        .indexed_iter()
        .find(|(_, &v)| weight(v).is_none())
        .map(|(at, v)| (at, v.to_string()));
    let cells = values.iter().map(|&v| weight(v).unwrap_or(1)).collect();
    (cells, bad)
}

/// Where a ROS map's cells lie in its map frame: the `map_server` YAML's `resolution`
/// (metres per cell) and `origin` (`(x, y, yaw)` of the bottom-left cell's lower-left
/// corner; the yaw is ignored, as by nav2's costmap). Row 0 is the image's top row. The
/// conversions are nav2's `Costmap2D::mapToWorld` and `worldToMap` with that row flip
/// (planner-maps' `MapFrame`).
#[pyclass(module = "gridplan", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct MapFrame {
    inner: planner_maps::MapFrame,
}

impl MapFrame {
    /// The map-frame position of cell `(x, y)`'s centre, or the `ValueError` of a cell off
    /// the map.
    fn point(&self, x: i64, y: i64) -> PyResult<(f64, f64)> {
        match to_cell((x, y)) {
            Some(c) if c.x < self.inner.width && c.y < self.inner.height => Ok(self.inner.world(c)),
            _ => Err(Failure::Value(format!(
                "MapFrame.world: cell ({x}, {y}) is not on the {}x{} map",
                self.inner.width, self.inner.height
            ))
            .into()),
        }
    }
}

#[pymethods]
impl MapFrame {
    /// Metres per cell.
    #[getter]
    fn resolution(&self) -> f64 {
        self.inner.resolution
    }

    /// `(x, y, yaw)` of the bottom-left cell's lower-left corner, as the YAML gives it.
    #[getter]
    fn origin(&self) -> (f64, f64, f64) {
        let [x, y, yaw] = self.inner.origin;
        (x, y, yaw)
    }

    /// The map's extent in metres: `(min_x, min_y, max_x, max_y)`.
    #[getter]
    fn bounds(&self) -> (f64, f64, f64, f64) {
        let [a, b, c, d] = self.inner.bounds();
        (a, b, c, d)
    }

    /// The map-frame position (metres) of a cell's centre: `world((x, y))` gives an
    /// `(x, y)` tuple of floats; `world(cells)` with an (N, 2) integer array (a path)
    /// gives an (N, 2) float64 array, row by row.
    fn world<'py>(&self, cells: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let py = cells.py();
        let array = py.import("numpy")?.call_method1("asarray", (cells,))?;
        let shape: Vec<usize> = array.getattr("shape")?.extract()?;
        let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
        let cells_hint = "MapFrame.world: expected a cell (x, y) or an (N, 2) array of cells";
        // One cell, as any other cell argument: integers of any size (those beyond int64
        // make an object array).
        if shape == [2] && matches!(kind.as_str(), "i" | "u" | "O") {
            let (x, y) = match given_cell("MapFrame.world", cells)? {
                GivenCell::At(x, y) => (x, y),
                GivenCell::Beyond(x, y) => {
                    return Err(Failure::Value(format!(
                        "MapFrame.world: cell ({x}, {y}) is not on the {}x{} map",
                        self.inner.width, self.inner.height
                    ))
                    .into())
                }
            };
            let point = self.point(x, y)?;
            return Ok(point.into_pyobject(py)?.into_any());
        }
        if kind != "i" && kind != "u" {
            return Err(Failure::Type(format!(
                "{cells_hint} (integers), got dtype {}",
                array.getattr("dtype")?.str()?
            ))
            .into());
        }
        let converted = array.call_method1("astype", ("int64",))?;
        match shape.as_slice() {
            [_, 2] => {
                let view: PyReadonlyArray2<'_, i64> = converted.extract()?;
                let view = view.as_array();
                let mut out = Array2::<f64>::zeros((view.nrows(), 2));
                for (row, cell) in view.rows().into_iter().enumerate() {
                    let (x, y) = self.point(cell[0], cell[1])?;
                    out[[row, 0]] = x;
                    out[[row, 1]] = y;
                }
                Ok(PyArray2::from_owned_array(py, out).into_any())
            }
            _ => Err(Failure::Value(format!(
                "{cells_hint}, got shape {}",
                array.getattr("shape")?.str()?
            ))
            .into()),
        }
    }

    /// Pickling (and `copy`): the resolution, origin and size.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let frame = slf.get().inner;
        let state = (frame.resolution, frame.origin, frame.width, frame.height);
        Ok((
            slf.get_type().getattr("_from_state")?,
            state.into_pyobject(slf.py())?,
        ))
    }

    /// The frame `__reduce__` describes.
    #[classmethod]
    #[pyo3(name = "_from_state")]
    fn from_state(
        _cls: &Bound<'_, pyo3::types::PyType>,
        resolution: f64,
        origin: [f64; 3],
        width: u32,
        height: u32,
    ) -> PyResult<MapFrame> {
        // As the YAML reader: map positions need a positive resolution.
        if !(resolution > 0.0 && resolution.is_finite()) {
            return Err(Failure::Value(format!(
                "MapFrame: resolution {resolution} is not a positive number"
            ))
            .into());
        }
        Ok(MapFrame {
            inner: planner_maps::MapFrame {
                resolution,
                origin,
                width,
                height,
            },
        })
    }

    /// The cell `(x, y)` holding map-frame point `point = (x, y)` (metres); ValueError for
    /// a point outside the map (the lower and left edges are inside, the upper and right
    /// ones outside, as nav2 has them).
    fn cell(&self, point: (f64, f64)) -> PyResult<(u32, u32)> {
        let (x, y) = point;
        match self.inner.cell_at(x, y) {
            Some(c) => Ok((c.x, c.y)),
            None => Err(Failure::Value(format!(
                "MapFrame.cell: point ({}, {}) lies outside the map, which spans {}",
                metres(x),
                metres(y),
                self.inner.extent()
            ))
            .into()),
        }
    }

    fn __repr__(&self) -> String {
        let [x, y, yaw] = self.inner.origin.map(metres);
        format!(
            "MapFrame(resolution={}, origin=({x}, {y}, {yaw}), width={}, height={})",
            metres(self.inner.resolution),
            self.inner.width,
            self.inner.height
        )
    }
}

/// A number of metres (or radians) for a message: as written (`0.05`, `-10`) unless that
/// takes more than 20 characters, then in exponent form (`1e300`, `-1.5e-300`), so that
/// an origin of `1e308` does not print 309 digits.
fn metres(value: f64) -> String {
    let plain = value.to_string();
    if plain.len() > 20 {
        format!("{value:e}")
    } else {
        plain
    }
}
