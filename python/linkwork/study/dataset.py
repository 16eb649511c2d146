"""A study's results as a labelled dataset: xarray (NetCDF) or pandas (Parquet), with
units. Coordinates: ``design`` (the index), one per parameter along it (its values),
``time`` along ``step``; variables: one per output, and ``error``."""

from __future__ import annotations

import json
import os
from typing import TYPE_CHECKING, Any

import numpy as np

from .._args import requires
from ..errors import StudyError

if TYPE_CHECKING:
    from linkwork.study import StudyResult

__all__ = ["to_xarray", "to_pandas", "save", "open_dataset", "coordinate_name"]


def coordinate_name(parameter: str) -> str:
    """The dataset's name of a parameter's coordinate ("length crank" -> "length_crank")."""
    return "".join(c if c.isalnum() or c == "_" else "_" for c in parameter).strip("_")


def _attrs(res: StudyResult) -> dict[str, Any]:
    return {
        "model": res.model_name,
        "designs": res.designs.kind,
        "seed": -1 if res.designs.seed is None else int(res.designs.seed),
        "grid_shape": json.dumps(list(res.designs.shape or [])),
        "parameters": json.dumps([p.name for p in res.parameters]),
        "outputs": json.dumps([o.name for o in res.outputs]),
        "derivatives": int(res.derivatives),
        "model_units": json.dumps(res.model_units),
        "failed": int(res.n_failed),
    }


def to_xarray(res: StudyResult) -> Any:
    xr = requires("xarray")
    n = len(res)
    coords: dict[str, Any] = {"design": ("design", np.arange(n)), "time": ("step", res.times, {"units": "s"})}
    for k, p in enumerate(res.parameters):
        coords[coordinate_name(p.name)] = (
            "design",
            res.designs.values[:, k],
            {"units": p.unit, "parameter": p.name},
        )
    data: dict[str, Any] = {}
    for o in res.outputs:
        values = res.figures[o.key]
        if o.dtype == "str":
            values = values.astype(str)
        data[o.key] = (("design", *o.dims), values, {"units": o.unit, "output": o.name})
    data["error"] = (("design",), res.errors.astype(str), {"meaning": "empty where the design swept"})
    return xr.Dataset(data, coords=coords, attrs=_attrs(res))


def to_pandas(res: StudyResult) -> Any:
    pd = requires("pandas")
    cols: dict[str, Any] = {"design": np.arange(len(res))}
    for k, p in enumerate(res.parameters):
        cols[coordinate_name(p.name)] = res.designs.values[:, k]
    for o in res.outputs:
        if not o.dims:
            cols[o.key] = res.figures[o.key].astype(str) if o.dtype == "str" else res.figures[o.key]
    cols["error"] = res.errors.astype(str)
    frame = pd.DataFrame(cols).set_index("design")
    frame.attrs["units"] = _units(res)
    return frame


def _units(res: StudyResult) -> dict[str, str]:
    units = {coordinate_name(p.name): p.unit for p in res.parameters}
    units.update({o.key: o.unit for o in res.outputs})
    units["time"] = "s"
    return units


def save(res: StudyResult, path: str) -> str:
    path = os.fspath(path)
    if path.endswith(".nc"):
        requires("h5netcdf")
        requires("h5py")
        ds = to_xarray(res)
        ds.to_netcdf(path, engine="h5netcdf")
        return path
    if path.endswith(".parquet"):
        pa = requires("pyarrow")
        pq = requires("pyarrow.parquet")
        names, arrays, fields = [], [], []
        units = _units(res)

        def add(name: str, values: np.ndarray, unit: str, meaning: str = "") -> None:
            if values.ndim == 1:
                arr = pa.array(values.astype(str) if values.dtype == object else values)
            else:
                flat = pa.array(np.ascontiguousarray(values, dtype=np.float64).ravel())
                arr = pa.FixedSizeListArray.from_arrays(flat, int(np.prod(values.shape[1:])))
            meta = {"units": unit, "shape": json.dumps(list(values.shape[1:]))}
            if meaning:
                meta["meaning"] = meaning
            names.append(name)
            arrays.append(arr)
            fields.append(pa.field(name, arr.type, metadata=meta))

        add("design", np.arange(len(res)), "")
        for k, p in enumerate(res.parameters):
            add(coordinate_name(p.name), res.designs.values[:, k], p.unit, p.name)
        for o in res.outputs:
            add(o.key, res.figures[o.key], o.unit, o.name)
        add("error", res.errors, "", "empty where the design swept")
        meta = {k: str(v) for k, v in _attrs(res).items()}
        meta["units"] = json.dumps(units)
        meta["times"] = json.dumps(res.times.tolist())
        schema = pa.schema(fields, metadata=meta)
        pq.write_table(pa.Table.from_arrays(arrays, schema=schema), path)
        return path
    raise StudyError(f"{path}: a study's dataset is written as .nc (NetCDF) or .parquet")


def open_dataset(path: str) -> Any:
    """A saved study's dataset as xarray (from .nc or .parquet), units included."""
    path = os.fspath(path)
    xr = requires("xarray")
    if path.endswith(".nc"):
        requires("h5netcdf")
        requires("h5py")
        return xr.load_dataset(path, engine="h5netcdf")
    if path.endswith(".parquet"):
        pq = requires("pyarrow.parquet")
        table = pq.read_table(path)
        meta = {k.decode(): v.decode() for k, v in (table.schema.metadata or {}).items()}
        times = np.asarray(json.loads(meta.pop("times")))
        parameters = json.loads(meta["parameters"])
        coord_names = {coordinate_name(p) for p in parameters}
        coords: dict[str, Any] = {"time": ("step", times, {"units": "s"})}
        data: dict[str, Any] = {}
        for f in table.schema:
            fmeta = {k.decode(): v.decode() for k, v in (f.metadata or {}).items()}
            shape = json.loads(fmeta.get("shape", "[]"))
            col = table.column(f.name).combine_chunks()
            if shape:
                values = np.asarray(col.flatten().to_numpy()).reshape(len(col), *shape)
            else:
                values = col.to_numpy(zero_copy_only=False)
            dims = ("design", *(("step", "xy")[: len(shape)] if len(shape) < 2 else ("step", "xy")))
            if len(shape) == 1 and shape[0] == 2 and len(times) != 2:
                dims = ("design", "xy")
            attrs = {"units": fmeta.get("units", "")}
            if f.name == "design":
                coords["design"] = ("design", values)
            elif f.name in coord_names:
                coords[f.name] = ("design", values, {**attrs, "parameter": fmeta.get("meaning", "")})
            else:
                attrs["output" if f.name != "error" else "meaning"] = fmeta.get("meaning", "")
                data[f.name] = (dims, values, attrs)
        meta.pop("units", None)
        return xr.Dataset(data, coords=coords, attrs=meta)
    raise StudyError(f"{path}: a study's dataset is read from .nc (NetCDF) or .parquet")
