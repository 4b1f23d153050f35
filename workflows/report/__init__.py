"""The report of `dnarod compare`: DIR/results.json and DIR/report/index.html (`report`),
built from the files the steps (workflows/steps/) wrote; the matched comparison
(`comparison`) and the coarse-graining loop's entries (`prediction`)."""
