"""Label images given from Python as numpy arrays.

An image input may be {"labels": array, "spacing": [sx, sy, sz], "origin": [x, y, z]} instead
of a file path. The array is written to a temporary NRRD file and the job gets its path, so
the core reads it with the same reader as a file from 3D Slicer or SimpleITK.

Axis order: labels[z][y][x] by default (numpy's C order with x fastest, the order of
SimpleITK.GetArrayFromImage and of NRRD data), or labels[x][y][z] with "axes": "xyz" (the
order of nibabel's get_fdata()). spacing and origin are always (x, y, z); origin is the
centre of the voxel with index 0 on every axis, spacing the voxel size in model units (mm).
"""
import gzip
import os

from ._core import InputError

# numpy dtype -> NRRD type; other integer dtypes are converted when their values fit.
_NRRD_TYPES = {"uint8": "uint8", "int8": "int8", "uint16": "uint16", "int16": "int16",
               "uint32": "uint32", "int32": "int32"}


def write_nrrd(path, labels, spacing=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0), axes="zyx", where="image"):
    """Write a 3D integer label array as a gzip-encoded NRRD file."""
    import numpy as np
    labels = np.asarray(labels)
    if labels.ndim != 3:
        raise InputError("%s: 'labels' must be a 3D array, got %d dimensions" % (where, labels.ndim))
    if labels.dtype == bool:
        labels = labels.astype(np.uint8)
    if not np.issubdtype(labels.dtype, np.integer):
        raise InputError("%s: 'labels' must be an integer array (got %s): round or cast the segmentation, "
                         "e.g. labels.astype(numpy.int32)" % (where, labels.dtype))
    if labels.dtype.name not in _NRRD_TYPES:
        lo, hi = (int(labels.min()), int(labels.max())) if labels.size else (0, 0)
        if lo < -2 ** 31 or hi >= 2 ** 31:
            raise InputError("%s: labels range from %d to %d, beyond 32 bits: renumber them" % (where, lo, hi))
        labels = labels.astype(np.int32)
    if axes == "xyz":
        labels = labels.transpose(2, 1, 0)
    elif axes != "zyx":
        raise InputError("%s: 'axes' must be 'zyx' (labels[z][y][x], the default) or 'xyz'" % where)
    for key, value in (("spacing", spacing), ("origin", origin)):
        try:
            values = [float(v) for v in value]
        except (TypeError, ValueError):
            values = []
        if len(values) != 3:
            raise InputError("%s: '%s' must be three numbers (x, y, z)" % (where, key))
    if not all(float(s) > 0 for s in spacing):
        raise InputError("%s: spacing %s has a non-positive voxel size: give positive sizes in model "
                         "units (mm)" % (where, list(spacing)))
    data = np.ascontiguousarray(labels, dtype=labels.dtype.newbyteorder("<"))
    nz, ny, nx = data.shape
    header = ("NRRD0004\n"
              "# written by oraclemesh from a numpy array\n"
              "type: %s\ndimension: 3\nspace dimension: 3\nsizes: %d %d %d\n"
              "space directions: (%r,0,0) (0,%r,0) (0,0,%r)\nspace origin: (%r,%r,%r)\n"
              "endian: little\nencoding: gzip\n\n"
              % ((_NRRD_TYPES[labels.dtype.name], nx, ny, nz) + tuple(float(s) for s in spacing)
                 + tuple(float(o) for o in origin)))
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        # mtime=0: the same array gives the same bytes (determinism, cache-friendliness).
        f.write(gzip.compress(data.tobytes(), compresslevel=1, mtime=0))


def with_image_files(job, directory):
    """The job with every image given as an array replaced by the path of an NRRD file
    written into `directory`. The caller's job is not modified."""
    if not isinstance(job, dict) or not isinstance(job.get("inputs"), list):
        return job
    inputs = []
    for index, entry in enumerate(job["inputs"]):
        if isinstance(entry, dict) and isinstance(entry.get("image"), dict):
            image = entry["image"]
            where = "input '%s'" % entry.get("name", "input %d" % (index + 1))
            unknown = set(image) - {"labels", "spacing", "origin", "axes"}
            if unknown or "labels" not in image or "spacing" not in image:
                raise InputError("%s: an image given from Python is {\"labels\": array, \"spacing\": [sx, sy, sz], "
                                 "\"origin\": [x, y, z], \"axes\": \"zyx\"}; %s" % (
                                     where, "unknown keys %s" % sorted(unknown) if unknown else
                                     "'labels' is missing" if "labels" not in image else
                                     "'spacing' (voxel size in mm) is missing"))
            path = os.path.join(directory, "image%d.nrrd" % index)
            write_nrrd(path, image["labels"], image["spacing"],
                       image.get("origin", (0.0, 0.0, 0.0)), image.get("axes", "zyx"), where)
            entry = dict(entry, image=path)
        inputs.append(entry)
    return dict(job, inputs=inputs)
