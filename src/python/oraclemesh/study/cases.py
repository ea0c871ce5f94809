"""From the batch's JOBS arguments to cases: job files, folders of them, study files, dicts.

A case is what one worker runs: the job as the core will read it (input paths absolute,
output paths relative to the case's own folder), the study parameters that made it, the
environment of its child process, and the hash that decides whether a rerun may reuse it.
The study file format and the hash rule are described in oraclemesh.study's docstring.
"""
import copy
import hashlib
import itertools
import json
import os
import re

from .. import InputError, _core

# Input kinds that name a file the core reads.
FILE_KEYS = ("file", "image")
STUDY_KEYS = {"study", "base", "parameters", "cases", "set", "environment", "name", "group_by", "x"}
CASE_KEYS = {"name", "parameters", "set", "environment", "columns"}
LEVEL_KEYS = {"value", "set", "columns"}


class Case:
    """One job of the batch, ready to hash and to send."""

    def __init__(self, name, job, source, parameters=None, environment=None, columns=None):
        self.name = name
        self.job = job                          # input paths absolute, outputs relative
        self.source = source                    # the job or study file it came from
        self.parameters = parameters or {}      # study parameter -> level value
        self.columns = columns or {}            # extra per-case values for the table
        self.environment = environment or {}    # variables for the case's child process
        self.missing = [p for p in input_files(job) if not os.path.isfile(p)]
        self.hash = case_hash(job, self.environment)

    def __repr__(self):
        return "<Case %s>" % self.name


def collect(jobs):
    """The cases of a list of job files, folders, study files, job dicts and study dicts.
    Returns (cases, study options): options merge the studies' "group_by" and "x"."""
    if isinstance(jobs, (str, os.PathLike, dict)):
        jobs = [jobs]
    cases, options = [], {}
    for number, item in enumerate(jobs):
        if isinstance(item, dict):  # named by its place among the jobs
            found, opts = _from_object(item, os.getcwd(), "job-%d" % (number + 1))
        else:
            path = os.path.abspath(os.fspath(item))
            if os.path.isdir(path):
                found, opts = _from_folder(path)
            else:
                found, opts = _from_file(path, explicit=True)
        cases += found
        for key, value in opts.items():
            options.setdefault(key, value)
    if not cases:
        raise InputError("no jobs found in %s: give job files (.json), folders of them or study files"
                         % ", ".join(map(str, jobs)))
    _unique_names(cases)
    return cases, options


def _from_folder(folder):
    cases, options = [], {}
    for name in sorted(os.listdir(folder)):
        path = os.path.join(folder, name)
        if name.endswith(".json") and os.path.isfile(path):
            found, opts = _from_file(path, explicit=False)
            cases += found
            for key, value in opts.items():
                options.setdefault(key, value)
    return cases, options


def _from_file(path, explicit):
    _core.require_job_file_size(path)  # over the limit: refused by its size, before it is read
    try:
        with open(path) as f:
            data = json.load(f)
    except OSError as e:
        raise InputError("cannot read the job file '%s': %s" % (path, e.strerror)) from None
    except ValueError as e:
        if not explicit:
            return [], {}
        raise InputError("the job file '%s' is not valid JSON: %s" % (path, e)) from None
    kind = kind_of(data)
    if kind is None:
        if explicit:
            raise InputError("'%s' is neither a job (an object with 'inputs') nor a study file (an "
                             "object with 'base')" % path)
        return [], {}  # a report or another JSON file in a folder of jobs
    stem = os.path.splitext(os.path.basename(path))[0]
    return _from_object(data, os.path.dirname(path), stem, kind, source=path)


def kind_of(data):
    """'study', 'job' or None (reports also have 'inputs', but with 'counts' next to them)."""
    if not isinstance(data, dict):
        return None
    if "base" in data:
        return "study"
    if isinstance(data.get("inputs"), list) and "counts" not in data:
        return "job"
    return None


def _from_object(data, folder, stem, kind=None, source=None):
    kind = kind or kind_of(data)
    if kind == "study" or (kind is None and "base" in data):
        return _from_study(data, folder, stem, source or "<study %s>" % stem)
    job = _with_absolute_inputs(data, folder)
    return [Case(stem, _with_relative_outputs(job), source or stem)], {}


def _from_study(study, folder, stem, source):
    unknown = set(study) - STUDY_KEYS
    if unknown:
        raise InputError("study %s: unknown keys %s (known: %s)" % (source, ", ".join(sorted(unknown)),
                                                                   ", ".join(sorted(STUDY_KEYS))))
    base = study["base"]
    if isinstance(base, str):
        base_path = os.path.join(folder, base)
        _core.require_job_file_size(base_path)
        try:
            with open(base_path) as f:
                base = json.load(f)
        except (OSError, ValueError) as e:
            raise InputError("study %s: cannot read its base job '%s': %s" % (source, base_path, e)) from None
        base = _with_absolute_inputs(base, os.path.dirname(base_path))
    elif isinstance(base, dict):
        base = _with_absolute_inputs(base, folder)
    else:
        raise InputError("study %s: 'base' must be a job file path or a job object" % source)
    common = study.get("set", {})
    environment = study.get("environment", {})
    name_format = study.get("name")
    study_name = study.get("study", stem)
    cases = []
    for number, spec in enumerate(_case_specs(study, source)):
        job = apply_settings(base, common, source)
        job = apply_settings(job, spec["set"], source)
        job = _with_relative_outputs(_with_absolute_inputs(job, folder))
        env = dict(environment, **spec.get("environment", {}))
        name = spec.get("name") or _case_name(study_name, name_format, spec["parameters"], number, source)
        cases.append(Case(name, job, source, spec["parameters"], env, spec.get("columns")))
    options = {key: study[key] for key in ("group_by", "x") if key in study}
    return cases, options


def _case_specs(study, source):
    """The grid of the study's parameters (every combination, first parameter slowest), then
    its explicit "cases"."""
    parameters = study.get("parameters", {})
    if not isinstance(parameters, dict):
        raise InputError("study %s: 'parameters' must map each parameter to its levels" % source)
    axes = [[(name, level) for level in _levels(name, levels, source)] for name, levels in parameters.items()]
    specs = []
    if axes:
        for combination in itertools.product(*axes):
            spec = {"parameters": {}, "set": {}, "columns": {}}
            for name, level in combination:
                spec["parameters"][name] = level["value"]
                spec["set"].update(level.get("set", {}))
                spec["columns"].update(level.get("columns", {}))
            specs.append(spec)
    for i, case in enumerate(study.get("cases", [])):
        if not isinstance(case, dict) or set(case) - CASE_KEYS:
            raise InputError("study %s: cases[%d] must be an object with keys among %s"
                             % (source, i, ", ".join(sorted(CASE_KEYS))))
        specs.append({"parameters": case.get("parameters", {}), "set": case.get("set", {}),
                      "columns": case.get("columns", {}), "environment": case.get("environment", {}),
                      "name": case.get("name")})
    if not specs:
        raise InputError("study %s has neither 'parameters' nor 'cases': it makes no job" % source)
    return specs


def _levels(name, levels, source):
    """A parameter's levels: [{"value": v, "set": {...}}, ...] or {"path": p, "values": [...]}."""
    if isinstance(levels, dict) and set(levels) == {"path", "values"}:
        return [{"value": v, "set": {levels["path"]: v}} for v in levels["values"]]
    if isinstance(levels, list) and levels and all(isinstance(l, dict) and "value" in l
                                                   and not set(l) - LEVEL_KEYS for l in levels):
        return levels
    raise InputError("study %s: parameter '%s' must be a list of levels {\"value\": v, \"set\": "
                     "{\"path.to.key\": value}} or {\"path\": \"path.to.key\", \"values\": [...]}" % (source, name))


def apply_settings(job, settings, source):
    """A copy of job with each "a.b.0.c": value of settings set (null removes the key).
    Path parts index lists where the container is a list and are keys elsewhere."""
    job = copy.deepcopy(job)
    for path, value in settings.items():
        parts = path.split(".")
        node = job
        try:
            for part in parts[:-1]:
                node = node[int(part)] if isinstance(node, list) else node.setdefault(part, {})
            last = parts[-1]
            if isinstance(node, list):
                node[int(last)] = value
            elif value is None:
                node.pop(last, None)
            else:
                node[last] = value
        except (ValueError, IndexError, TypeError, AttributeError):
            raise InputError("study %s: cannot set '%s' in the base job (no such list entry or "
                             "object)" % (source, path)) from None
    return job


def _case_name(study_name, name_format, parameters, number, source):
    if name_format:
        try:
            name = name_format.format(**parameters)
        except (KeyError, ValueError, IndexError) as e:
            raise InputError("study %s: the case name template '%s' does not fit the parameters "
                             "(%s)" % (source, name_format, e)) from None
    elif parameters:
        name = study_name + "-" + "-".join("%s%s" % (k, v) for k, v in parameters.items())
    else:
        name = "%s-%d" % (study_name, number + 1)
    return name


def _unique_names(cases):
    """Case names become folder names: made safe, and unique by a suffix in order."""
    seen = set()
    for case in cases:
        base = re.sub(r"[^A-Za-z0-9._=+-]+", "_", case.name).strip("._") or "case"
        name, k = base, 2
        while name in seen:
            name, k = "%s-%d" % (base, k), k + 1
        seen.add(name)
        case.name = name


def _with_absolute_inputs(job, folder):
    if not isinstance(job, dict):
        raise InputError("a job must be a JSON object with an 'inputs' list")
    job = copy.deepcopy(job)
    for entry in job.get("inputs", []) if isinstance(job.get("inputs"), list) else []:
        for key in FILE_KEYS:
            if isinstance(entry, dict) and isinstance(entry.get(key), str):
                entry[key] = os.path.normpath(os.path.join(folder, entry[key]))
    return job


def _with_relative_outputs(job):
    """A case writes its outputs into its own folder: each output keeps its file name only."""
    output = job.get("output")
    if isinstance(output, dict):
        if isinstance(output.get("files"), list):
            output["files"] = [os.path.basename(f) if isinstance(f, str) else f for f in output["files"]]
        if isinstance(output.get("report"), str):
            output["report"] = os.path.basename(output["report"])
    return job


def output_names(job):
    output = job.get("output") if isinstance(job.get("output"), dict) else {}
    names = [f for f in output.get("files", []) if isinstance(f, str)]
    if isinstance(output.get("report"), str):
        names.append(output["report"])
    return names


def input_files(job):
    """Every file the core reads for this job: input files and detached NRRD data files."""
    files = []
    for entry in job.get("inputs", []) if isinstance(job.get("inputs"), list) else []:
        for key in FILE_KEYS:
            path = entry.get(key) if isinstance(entry, dict) else None
            if isinstance(path, str):
                files.append(path)
                if key == "image":
                    files += _nrrd_data_files(path)
    return files


def _nrrd_data_files(path):
    try:
        with open(path, "rb") as f:
            header = f.read(65536).split(b"\n\n", 1)[0].decode("latin-1")
    except OSError:
        return []
    for line in header.splitlines():
        key, _, value = line.partition(":")
        if key.strip().lower() in ("data file", "datafile") and not value.strip().startswith("LIST"):
            name = value.strip().split()[0] if value.strip() else ""
            if name and "%" not in name:
                return [os.path.join(os.path.dirname(path), name)]
    return []


_DIGESTS = {}  # (path, size, mtime) -> SHA-256: a study reads the same inputs for every case


def file_digest(path):
    """SHA-256 of a file's bytes."""
    st = os.stat(path)
    key = (path, st.st_size, st.st_mtime_ns)
    if key not in _DIGESTS:
        h = hashlib.sha256()
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
        _DIGESTS[key] = h.hexdigest()
    return _DIGESTS[key]


def case_hash(job, environment):
    """SHA-256 of the job with each input file replaced by the hash of its bytes (and its
    extension, which picks the reader), of the detached data files, and of the environment."""
    job = copy.deepcopy(job)
    extra = []
    for entry in job.get("inputs", []) if isinstance(job.get("inputs"), list) else []:
        for key in FILE_KEYS:
            path = entry.get(key) if isinstance(entry, dict) else None
            if isinstance(path, str):
                entry[key] = _content_name(path)
                if key == "image":
                    extra += [_content_name(p) for p in _nrrd_data_files(path)]
    text = json.dumps({"job": job, "data_files": extra, "environment": environment},
                      sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def _content_name(path):
    extension = os.path.splitext(path)[1].lower()
    try:
        return "sha256:%s%s" % (file_digest(path), extension)
    except OSError:
        return "missing:%s" % path
