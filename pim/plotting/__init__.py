"""The presentation layer: the design sheet's graphs, the conventions drawing, Monte Carlo
histograms and the reconstruction's scene. Figures are :class:`matplotlib.figure.Figure`
objects; nothing here changes the caller's matplotlib backend.
"""
