"""What bench/transfer.py reports: the table of ratios and rank correlations per study,
build and gait set, every measured gait's record for transfer.json, and the figure of
achieved against predicted travel."""
import numpy as np
from scipy.stats import spearmanr


def agreement(pred, ach):
    """(ratio of sums, Spearman rho) of achieved against predicted where both are finite."""
    ok = np.isfinite(ach) & np.isfinite(pred)
    rho = spearmanr(pred[ok], ach[ok]).correlation if ok.sum() > 2 else float("nan")
    return ach[ok].sum() / pred[ok].sum(), rho


def table(sets, where, achieved, walls, validated):
    """One row per study, build, scenario and set; with --validate also the ratio and rho
    against the fresh ensemble's means (validated_*; nan for a study without one)."""
    rows = []
    for study in sets:
        for build, scen in where[study]:
            for kind in ("best", "spread"):
                pred = np.array([p for p, _ in sets[study][kind]])
                ach = np.array([achieved[(build, study, kind, i, scen)] for i in range(len(pred))])
                ok = np.isfinite(ach)
                ratio, rho = agreement(pred, ach)
                fresh = np.array(validated.get(study, {}).get(kind, [np.nan] * len(pred)))
                v_ratio, v_rho = agreement(fresh, ach) if np.isfinite(fresh).any() else (np.nan,) * 2
                rows.append({"study": study, "build": build, "scenario": scen, "set": kind,
                             "gaits": int(ok.sum()),
                             "predicted_cm": 100 * pred[ok].mean(),
                             "achieved_cm": 100 * ach[ok].mean(),
                             "ratio": ratio, "spearman": rho,
                             "validated_cm": 100 * np.nanmean(fresh[ok]) if ok.any() else np.nan,
                             "validated_ratio": v_ratio, "validated_spearman": v_rho,
                             "best_gait_cm": 100 * ach[0] if kind == "best" else float("nan"),
                             "wall_s": walls[study]})
    print(f"{'study':<44}{'build':<8}{'scenario':<22}{'set':<8}{'n':>3}{'pred cm':>9}{'real cm':>9}"
          f"{'ratio':>7}{'rho':>7}{'valid cm':>9}{'ratio':>7}{'rho':>7}{'best cm':>9}{'wall s':>8}")
    for r in rows:
        print(f"{r['study']:<44}{r['build']:<8}{r['scenario']:<22}{r['set']:<8}{r['gaits']:>3}"
              f"{r['predicted_cm']:>9.2f}{r['achieved_cm']:>9.2f}{r['ratio']:>7.2f}"
              f"{r['spearman']:>7.2f}{r['validated_cm']:>9.2f}{r['validated_ratio']:>7.2f}"
              f"{r['validated_spearman']:>7.2f}{r['best_gait_cm']:>9.2f}{r['wall_s']:>8.0f}")
    return rows


def per_gait(sets, where, achieved, validated):
    """Every measured gait: its genes, the study's prediction, the fresh ensemble's (None
    without --validate) and its travel on each (build, scenario), metres per cycle."""
    out = {}
    for study in sets:
        for kind, gaits in sets[study].items():
            fresh = validated.get(study, {}).get(kind, [None] * len(gaits))
            out[f"{study}/{kind}"] = [
                {"genes": g, "predicted": p, "validated": v,
                 "achieved": {f"{b}/{scen}": achieved[(b, study, kind, i, scen)]
                              for b, scen in where[study]}}
                for i, ((p, g), v) in enumerate(zip(gaits, fresh))]
    return out


def plot(gaits, path):
    """Achieved against predicted travel per gait, one panel per study and build with nothing
    concealed: the study's own prediction and, where there is one, the fresh ensemble's."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    panels = sorted({(key.split("/")[0], where) for key, rows in gaits.items() if rows
                     for where in rows[0]["achieved"] if where.endswith("nothing concealed")})
    if not panels:
        return
    fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 4), squeeze=False)
    for ax, (study, where) in zip(axes[0], panels):
        rows = gaits.get(f"{study}/best", []) + gaits.get(f"{study}/spread", [])
        rows = [r for r in rows if r["achieved"][where] is not None and np.isfinite(r["achieved"][where])]
        ach = np.array([100 * r["achieved"][where] for r in rows])
        pred = np.array([100 * r["predicted"] for r in rows])
        ax.scatter(pred, ach, s=14, label="study's ensemble mean")
        if all(r["validated"] is not None for r in rows):
            ax.scatter([100 * r["validated"] for r in rows], ach, s=14, marker="x",
                       label="fresh ensemble (validate)")
        lim = [min(0, np.nanmin(ach), np.nanmin(pred)), max(np.nanmax(ach), np.nanmax(pred))]
        ax.plot(lim, lim, "k:", lw=0.8, label="achieved = predicted")
        ax.set(title=f"{study}\non {where.split('/')[0]}", xlabel="predicted, cm per cycle",
               ylabel="achieved, cm per cycle")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path)
    print(f"wrote {path}")
