"""A JATOS study archive (``.jzip``) of the experiment.

JATOS (Lange et al. 2015) imports a study from a JZIP: a ZIP file holding the
study assets folder (the files JATOS serves; its name is the study's
``dirName``) and a ``.jas`` file, the study properties as JSON::

    attneave_study.jzip
    ├── attneave_exp.jas                 {"version": "3", "data": {uuid, title, dirName, componentList, ...}}
    └── attneave_exp/                    the experiment directory: index.html, task.js, images/, ...

(JATOS's documentation, "JATOS Study Archive (JZIP)", schema version 3). The
study has one component, the page; its JSON input holds the settings a lab
may change in JATOS without rebuilding (``completion_url``). JATOS serves
``jatos.js`` beside the component's HTML file, which the page includes.

The study's and component's UUIDs are derived from the study folder's name
(UUID version 5), so an archive of a rebuilt experiment updates the study
JATOS already has (JATOS asks before it overwrites) instead of adding a copy.

References
----------
.. [1] Lange, K., Kühn, S. & Filevich, E. (2015). "Just Another Tool for
       Online Studies" (JATOS): An easy solution for setup and management of
       web servers supporting online studies. PLOS ONE, 10(6), e0130834.
"""

from __future__ import annotations

import json
import re
import uuid
import zipfile
from pathlib import Path

__all__ = ["JAS_VERSION", "study_dir_name", "study_properties", "write_jzip"]

#: The version of JATOS's study-properties schema the .jas file follows.
JAS_VERSION = "3"
_NAMESPACE = uuid.UUID("6f1c2c55-3a53-4a0e-9a8e-5c1d3f0a7b21")  # attneave's, for uuid5


def study_dir_name(out):
    """The study assets folder's name for an experiment directory: ``attneave_`` + its name, made safe.

    Examples
    --------
    >>> study_dir_name("out/my exp (2)")
    'attneave_my_exp_2'
    """
    stem = re.sub(r"[^A-Za-z0-9_-]+", "_", Path(out).resolve().name if str(out) else "").strip("_-")
    return "attneave_" + (stem or "experiment")


def study_properties(dir_name, title, component_html, json_input, description=""):
    """The ``.jas`` content (a dict) of a one-component study.

    Parameters
    ----------
    dir_name : str
        The study assets folder's name.
    title : str
    component_html : str
        The component's HTML file, relative to the assets folder.
    json_input : dict
        The component's JSON input (``jatos.componentJsonInput`` in the page).
    description : str

    Examples
    --------
    >>> p = study_properties("attneave_x", "Points", "index.html", {})
    >>> p["version"], p["data"]["dirName"], p["data"]["componentList"][0]["htmlFilePath"]
    ('3', 'attneave_x', 'index.html')
    """
    def uid(what):
        return str(uuid.uuid5(_NAMESPACE, f"{dir_name}:{what}"))

    return {
        "version": JAS_VERSION,
        "data": {
            "uuid": uid("study"),
            "title": title,
            "description": description,
            "groupStudy": False,
            "linearStudy": True,
            "allowPreview": False,
            "dirName": dir_name,
            "comments": "Written by attneave experiment --jatos.",
            "jsonData": None,
            "endRedirectUrl": "",
            "studyEntryMsg": None,
            "componentList": [{
                "uuid": uid("component"),
                "title": title,
                "htmlFilePath": component_html,
                # a reload must come back to the page: it resumes the participant's trials
                "reloadable": True,
                "active": True,
                "comments": "",
                "jsonData": json.dumps(json_input, indent=2),
            }],
            "batchList": [{
                "uuid": uid("batch"),
                "title": "Default",
                "active": True,
                "maxActiveMembers": None,
                "maxTotalMembers": None,
                "maxTotalWorkers": None,
                "allowedWorkerTypes": ["Jatos", "PersonalSingle", "PersonalMultiple", "GeneralSingle",
                                       "GeneralMultiple"],
                "comments": None,
                "jsonData": None,
            }],
        },
    }


def write_jzip(path, assets, files, properties):
    """Write the archive: ``<dirName>/<file>`` for each of `files` under `assets`, and ``<dirName>.jas``.

    Parameters
    ----------
    path : Path
        The ``.jzip`` to write (its folder is being built, so it appears whole).
    assets : Path
        The folder whose files become the study assets.
    files : list of str
        Paths relative to `assets` (POSIX).
    properties : dict
        From :func:`study_properties`.
    """
    name = properties["data"]["dirName"]
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as z:
        z.writestr(f"{name}.jas", json.dumps(properties, indent=2, ensure_ascii=False) + "\n")
        for f in files:
            z.write(Path(assets) / f, f"{name}/{f}")
