"""Studies: does tactic A contain this fire better than tactic B? (``scripts/study STUDY.yaml``)

ROS-free: paired missions in process (``fire_mission.inprocess``) on local workers or a Dask
cluster (``fire_bench.sweep``), resumable results (:mod:`fire_study.store`), statistics
(:mod:`fire_study.stats`: scipy / statsmodels) and an HTML report (:mod:`fire_study.report`).
"""

from .errors import StudyError
from .spec import Arm, Study, load_study, study_from_dict

__all__ = ["Arm", "Study", "StudyError", "load_study", "study_from_dict"]
