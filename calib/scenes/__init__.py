"""Scenes: a TOML file declares materials, a mesh level, what to run and which outputs.

``schema`` validates a scene file into frozen dataclasses (``errors``: a validation error as one line), ``plan`` turns it into FE specs and a
cost estimate (``--dry-run``), ``run`` runs its stages, ``table`` calibrates every material of a
sweep resumably; the built-in scenes are in ``builtin/``.
"""
from calib.scenes.plan import calibration_spec, format_plan, plan, plan_summary, plastic_needed
from calib.scenes.run import run_scene, summary_lines
from calib.scenes.schema import Scene, SceneError, builtin_scenes, load_scene, parse_scene
from calib.scenes.table import finished_materials, run_table, table_folder, write_master_table

__all__ = ["Scene", "SceneError", "builtin_scenes", "load_scene", "parse_scene", "calibration_spec",
           "format_plan", "plan", "plan_summary", "plastic_needed", "run_scene", "summary_lines",
           "finished_materials", "run_table", "table_folder", "write_master_table"]
