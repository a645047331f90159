package dev.motionfusion.cli

import dev.motionfusion.core.calib.AllanCurve
import dev.motionfusion.core.calib.AllanResult
import dev.motionfusion.core.calib.NoiseTerms
import java.util.Locale
import kotlin.math.sqrt

/** The figure and table of `fusion allan`. */
internal object AllanPlot {
    private val AXES = listOf("x", "y", "z")
    private val COLORS = listOf("#1f77b4", "#d62728", "#2ca02c")

    /** Per sensor one log-log panel: the three axes' curves and, dashed, each axis' fitted N and K lines and B floor. */
    fun svg(r: AllanResult, title: String): String {
        val fig = SvgFigure(title, "cluster time τ (s)", xScale = Scale.Log, panelHeight = 360.0, legendWidth = 230.0)
        fun panel(label: String, curve: AllanCurve?, terms: List<NoiseTerms>?) {
            if (curve == null || terms == null || curve.tau.size < 3) return
            val t = curve.tau
            val ends = doubleArrayOf(t.first(), t.last())
            val curves = ArrayList<SvgFigure.Curve>()
            for (a in 0 until 3) curves += SvgFigure.Curve("${AXES[a]}", COLORS[a], t, curve.deviation[a])
            for (a in 0 until 3) {
                val nt = terms[a]
                if (nt.whiteNoise.isFinite()) curves += SvgFigure.Curve("${AXES[a]} N ${g(nt.whiteNoise)}", COLORS[a], ends, DoubleArray(2) { nt.whiteNoise / sqrt(ends[it]) }, dashed = true, guide = true)
                if (nt.randomWalk.isFinite()) curves += SvgFigure.Curve("${AXES[a]} K ${g(nt.randomWalk)}", COLORS[a], ends, DoubleArray(2) { nt.randomWalk * sqrt(ends[it] / 3.0) }, dashed = true, guide = true)
                if (nt.biasInstability.isFinite()) curves += SvgFigure.Curve("${AXES[a]} 0.664·B ${g(nt.biasInstability)}", COLORS[a], ends, DoubleArray(2) { nt.biasInstability * NoiseTerms.FLICKER_FACTOR }, dashed = true, guide = true)
            }
            fig.panel(SvgFigure.Panel(label, curves, yScale = Scale.Log))
        }
        panel("gyroscope Allan deviation (rad/s)", r.gyroscope, r.gyroscopeTerms)
        panel("accelerometer Allan deviation (m/s²)", r.accelerometer, r.accelerometerTerms)
        return fig.render()
    }

    /** A plain-text table of the noise terms. */
    fun table(r: AllanResult): String = buildString {
        fun rows(sensor: String, curve: AllanCurve?, terms: List<NoiseTerms>?, unit: String) {
            if (curve == null || terms == null) return
            appendLine("$sensor: ${curve.samples} samples at ${g(curve.rateHz)} Hz over ${String.format(Locale.ROOT, "%.0f", curve.samples / curve.rateHz)} s, ${curve.gaps} gaps")
            appendLine(String.format(Locale.ROOT, "  %-4s %-14s %-14s %-14s %s", "axis", "N ($unit/√Hz)", "B ($unit)", "K ($unit/s/√Hz)", "B at τ (s)"))
            for ((a, t) in terms.withIndex()) {
                val k = if (t.randomWalk.isFinite()) g(t.randomWalk) else "< ${g(t.randomWalkUpperBound)}"
                appendLine(String.format(Locale.ROOT, "  %-4s %-14s %-14s %-14s %s", AXES[a], g(t.whiteNoise), g(t.biasInstability), k, g(t.biasInstabilityTau)))
            }
        }
        rows("gyroscope", r.gyroscope, r.gyroscopeTerms, "rad/s")
        rows("accelerometer", r.accelerometer, r.accelerometerTerms, "m/s²")
    }

    private fun g(v: Double) = if (v.isFinite()) String.format(Locale.ROOT, "%.3g", v) else "n/a"
}
