"""Block-structured adaptive mesh refinement for the grid methods (SPEC
§3.8): the layout of a hierarchy, windows of blocks with their ghosts,
transfers between levels, the error estimators, block maps, the hierarchy's
state with refluxing and regridding, and time subcycling."""
