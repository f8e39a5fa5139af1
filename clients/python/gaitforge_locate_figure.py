"""The locating step's figure (gaitforge_locate.py --figure): per recording, the x and z
residuals against time (with the numeric variants' centroid residuals in grey) and the
RMS of the detrended residual by gait phase."""
import numpy as np


def figure(recs, slices, path, variants, phase_bins):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n = len(recs)
    fig, axes = plt.subplots(n, 3, figsize=(13, 2.8 * n), squeeze=False)
    for row, (rec, s) in enumerate(zip(recs, slices)):
        # One colour per marker, rear to front (the robot's own marker names).
        colors = plt.cm.viridis(np.linspace(0, 0.9, max(1, len(rec.markers))))
        for col, chans in enumerate((rec.xs, rec.zs)):
            ax = axes[row, col]
            for c in chans:
                ax.plot(rec.ts, 1000 * rec.res[c], lw=0.8,
                        color=colors[rec.markers.index(c.rpartition(".")[0])],
                        label=c.rpartition(".")[0])
            ax.axhline(0, color="grey", lw=0.6)
            ax.set_title(f"{rec.name}: {'x' if col == 0 else 'z'} residual (recorded - simulated)",
                         fontsize=8)
            ax.set_ylabel("mm", fontsize=8)
            ax.set_xlabel("simulated time (s)", fontsize=8)
            ax.tick_params(labelsize=7)
        for k, v in enumerate(v for v in (variants[row] if variants else []) if v.xs):
            axes[row, 0].plot(v.ts, 1000 * np.mean([v.res[c] for c in v.xs], axis=0), lw=0.6,
                              color="grey", alpha=0.7,
                              label="variants (centroid)" if k == 0 else None)
        axes[row, 0].legend(fontsize=6, ncol=3)
        ax = axes[row, 2]
        centres = (np.arange(phase_bins) + 0.5) / phase_bins
        w = 0.4 / phase_bins
        ax.bar(centres - w / 2, 1000 * np.array(s["phase"]["x_rms_m"], dtype=float), w, label="x")
        ax.bar(centres + w / 2, 1000 * np.array(s["phase"]["z_rms_m"], dtype=float), w, label="z")
        ax.set_xlim(0, 1)
        ax.set_title(f"{rec.name}: RMS of the detrended residual by gait phase", fontsize=8)
        ax.set_xlabel("phase (t mod T) / T", fontsize=8)
        ax.set_ylabel("mm", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path)
