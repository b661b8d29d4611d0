"""Training code of the PathTracedVolume denoiser (GuideNet, bilateral-grid reference)."""
