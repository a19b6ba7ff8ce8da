"""Studies that validate the pipeline: the Hertz limit, FE and runtime stability on extreme inputs."""
