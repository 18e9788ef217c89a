"""skred's post-processing: pictures of the deformed voxels (Post §5-7), animations, time
series and a self-contained HTML report, drawn with matplotlib from the VTU/CSV/JSON results."""
