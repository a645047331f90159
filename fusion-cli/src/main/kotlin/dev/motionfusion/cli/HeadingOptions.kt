package dev.motionfusion.cli

import dev.motionfusion.core.replay.HeadingTare
import dev.motionfusion.core.replay.HeadingTareSpec
import dev.motionfusion.core.replay.ReplayListener
import java.util.Locale

/** The heading tare options of `fusion replay` and `fusion export` (docs/CONVENTIONS.md, "Heading tare"). */
internal object HeadingOptions {
    val VALUED = setOf("--heading-offset", "--heading-tare")

    val HELP = """
        |Heading tare (the output frame turned about the up axis only; pitch, roll, the vertical unchanged):
        |  --heading-tare WHEN[=DEG]  set the heading (yaw_deg: the top edge's direction, from north
        |                       toward east) to DEG (default 0) at WHEN: start (the first orientation)
        |                       or a time in s of the output's t_s (the first orientation at or after it)
        |  --heading-offset DEG every heading grows by DEG
        |                       The world is then ENU turned about up (z still up); the offset is printed.
        |""".trimMargin()

    fun spec(o: Options): HeadingTareSpec? {
        val offset = o.double("--heading-offset")
        val tare = o.value("--heading-tare")
        if (offset != null && tare != null) throw UsageException("--heading-offset and --heading-tare exclude each other")
        if (offset != null) return HeadingTareSpec.offset(offset)
        if (tare == null) return null
        val whenText = tare.substringBefore('=')
        val deg = if ('=' in tare) tare.substringAfter('=').toDoubleOrNull()?.takeIf { it.isFinite() }
            ?: throw UsageException("--heading-tare: '${tare.substringAfter('=')}' is not a heading in degrees") else 0.0
        val at = if (whenText == "start") null else whenText.toDoubleOrNull()?.takeIf { it.isFinite() }
            ?: throw UsageException("--heading-tare expects start or a time in s, optionally =DEG (e.g. start, 12.5, 12.5=90), got '$tare'")
        return HeadingTareSpec.at(at, deg)
    }

    /**
     * [inner] with the tare of [spec] applied (itself without one). A tare at a time takes the heading
     * there from a first replay, run by [probe] into the listener it is given.
     */
    fun wrap(spec: HeadingTareSpec?, inner: ReplayListener, source: String, probe: (ReplayListener) -> Unit): HeadingTare? {
        spec ?: return null
        if (spec.offsetDeg == null && spec.atS == null) return HeadingTare.atStart(inner, Math.toRadians(spec.headingDeg))
        return HeadingTare.offset(inner, spec.offsetRad(source, probe))
    }

    /** The note on what was applied. */
    fun note(spec: HeadingTareSpec, tare: HeadingTare): String =
        "heading tare: every heading + ${fmt(Math.toDegrees(tare.offsetRad))} deg" +
            if (spec.offsetDeg == null) " (${fmt(spec.headingDeg)} deg at ${spec.atS?.let { "t = ${fmt(it)} s" } ?: "the first orientation"})" else ""

    fun fmt(v: Double): String = String.format(Locale.ROOT, "%.4f", v).trimEnd('0').trimEnd('.')
}
