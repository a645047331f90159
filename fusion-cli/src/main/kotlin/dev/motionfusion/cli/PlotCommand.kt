package dev.motionfusion.cli

import dev.motionfusion.core.input.QuaternionTableReader
import dev.motionfusion.core.input.RecordingFormat
import dev.motionfusion.core.replay.OrientationComparison
import dev.motionfusion.core.replay.ReplayCsvWriter
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.replay.Replayer
import dev.motionfusion.core.event.SessionStream
import java.io.PrintStream
import java.nio.file.Files
import java.util.Locale
import kotlin.math.roundToLong

/** `fusion plot INPUT -o FIGURE.svg`. */
internal class PlotCommand(private val err: PrintStream, private val outputs: Outputs) : Command {
    override val name = "plot"
    override val summary = "SVG figure of the replayed Euler angles, and the error vs truth or rotation vector"
    override val help = """
        |Usage: fusion plot INPUT -o FIGURE.svg [--angles android|aerospace] [--truth TRUTH.csv[.gz]] [filter settings]
        |
        |Replays INPUT (any input of fusion replay) and draws an SVG figure: the Euler angles
        |over time (degrees), and below them the angle error (total, heading, inclination, as
        |BROAD's metric, over every sample: fusion eval scores a trial's scored rows only) against,
        |in this order of preference:
        |  the truth: a session's truth.csv, --truth FILE (t_s,qw,qx,qy,qz; t_s on the replay's
        |  time axis), or truth.csv[.gz] beside input.csv[.gz] of a trial folder;
        |  the phone's rotation vector recorded in the session.
        |Long recordings are reduced to per-pixel minimum/maximum, so spikes stay visible.
        |A session's markers (markers.csv) are drawn as labelled vertical lines.
        |
        |Options:
        |  -o, --output FILE    the SVG to write (required)
        |  --angles KIND        android: azimuth, pitch, roll (default); aerospace: yaw, pitch, roll
        |  --truth FILE         the truth table to draw the error against
        |  --quiet              no notes on standard error (warnings and errors still)
        |
        |${FilterOptions.HELP}
        |${InputOptions.HELP}""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val o = Options(args, setOf("-o", "--output", "--angles", "--truth") + FilterOptions.VALUED + InputOptions.VALUED, setOf("--quiet") + FilterOptions.FLAGS)
        val input = o.positional.singleOrNull() ?: throw UsageException("plot needs one INPUT")
        val output = o.value("-o") ?: o.value("--output") ?: throw UsageException("plot needs -o FIGURE.svg")
        val aerospace = when (o.value("--angles")?.lowercase() ?: "android") {
            "android" -> false
            "aerospace" -> true
            else -> throw UsageException("--angles expects android or aerospace")
        }
        FilterOptions.settings(o) // usage errors before the input is opened
        val inputPath = InputOptions.path(input)
        InputOptions.open(input, o, err, name).use { rec ->
            val settings = FilterOptions.settings(o, rec, err, name)
            // Read before the replay: each read of a zip counts against the decompression limit anew.
            val markers = rec.markers()
            val besideTable = rec.format == RecordingFormat.IMU_TABLE && Files.isDirectory(inputPath)
            val truthPath = o.value("--truth")?.let { InputOptions.path(it) }
                ?: if (besideTable) listOf("truth.csv.gz", "truth.csv").map { inputPath.resolve(it) }.firstOrNull { Files.isRegularFile(it) } else null
            // The truth table is read along with the replay, row by row.
            val truthTable = truthPath?.let { QuaternionTableReader.open(it, InputOptions.limits(o)) }
            var truthPending = truthTable?.next() == true
            val reference: SessionStream? = when {
                truthTable != null -> null
                SessionStream.TRUTH in rec.streams -> SessionStream.TRUTH
                SessionStream.ROTATION_VECTOR in rec.streams -> SessionStream.ROTATION_VECTOR
                else -> null
            }
            val refLabel = when {
                truthTable != null -> "truth (${truthPath!!.fileName})"
                reference == SessionStream.TRUTH -> "truth"
                reference == SessionStream.ROTATION_VECTOR -> "the phone's rotation vector"
                else -> null
            }
            val angles = Array(3) { Envelope() }
            val errors = Array(3) { Envelope() }
            var origin = rec.originNs
            val comparison = OrientationComparison { t, total, heading, incl ->
                val ts = Replayer.secondsBetween(origin ?: 0L, t)
                errors[0].add(ts, total); errors[1].add(ts, heading); errors[2].add(ts, incl)
            }
            val derived = DoubleArray(9)
            var truthRows = 0L
            val listener = object : ReplayListener {
                override fun step(step: ReplayStep) {
                    if (origin == null) origin = step.timestampNs - (step.timeS * 1e9).roundToLong()
                    if (truthTable != null) {
                        while (truthPending && truthTable.timeS <= step.timeS + 1e-7) {
                            truthRows++
                            val q = truthTable.q
                            comparison.reference(origin!! + (truthTable.timeS * 1e9).roundToLong(), q[0], q[1], q[2], q[3])
                            truthPending = truthTable.next()
                        }
                    }
                    if (!step.initialised) return
                    comparison.estimate(step.timestampNs, step.orientation)
                    ReplayCsvWriter.derived(step.orientation, step.specificForce, derived)
                    val base = if (aerospace) 3 else 0
                    for (k in 0 until 3) angles[k].add(step.timeS, derived[base + k])
                }

                override fun reference(stream: SessionStream, timestampNs: Long, values: DoubleArray) {
                    if (stream != reference) return
                    if (stream == SessionStream.TRUTH) comparison.reference(timestampNs, values[0], values[1], values[2], values[3])
                    else comparison.reference(timestampNs, values[3], values[0], values[1], values[2])
                }
            }
            val progress = Progress(err, "plot", rec.metadata?.streams?.values?.sumOf { it.samples })
            truthTable.use {
                ReplayCommand.replay(rec, null, settings, null, listener, progress::update)
                if (truthTable != null) while (truthPending) { truthRows++; truthPending = truthTable.next() }
            }
            progress.finish()
            if (angles[0].isEmpty) throw dev.motionfusion.core.io.DataFormatException(input, 0, 0, "the filter produced no orientation (no gyroscope with accelerometer samples)")
            // A truth on another time axis (ms, or another clock) meets the replay in a few rows at most: refused, as eval --truth refuses it.
            if (truthTable != null && comparison.total.count * 2 < truthRows) {
                throw dev.motionfusion.core.io.DataFormatException(truthPath.toString(), 0, 0, "only ${comparison.total.count} of its $truthRows rows " +
                    "fall within the replay (0–${String.format(Locale.ROOT, "%.3f", angles[0].lastT)} s): t_s must be seconds on the replay's time axis")
            }
            val tMax = angles.maxOf { it.lastT }
            val marks = markers.map { SvgFigure.Mark(Replayer.secondsBetween(origin ?: 0L, it.timestampNs), it.label) }
            val outside = marks.count { it.t < 0.0 || it.t > tMax }
            val fig = SvgFigure("fusion replay of ${rec.name}", "time (s)", xMin = 0.0, xMax = tMax, marks = marks)
            val names = if (aerospace) listOf("yaw", "pitch", "roll") else listOf("azimuth", "pitch", "roll")
            val colors = listOf("#1f77b4", "#d62728", "#2ca02c")
            fig.panel(SvgFigure.Panel("${if (aerospace) "aerospace" else "Android"} angles (°)",
                names.indices.map { angles[it].curve(names[it], colors[it], wraps = it != 1) }, -180.0, 180.0, 90.0))
            if (refLabel != null && !errors[0].isEmpty) {
                val labels = listOf("total", "heading", "inclination")
                val c2 = listOf("#000000", "#ff7f0e", "#9467bd")
                fig.panel(SvgFigure.Panel("error vs $refLabel (°)", labels.indices.map { errors[it].curve(labels[it], c2[it], wraps = false) }, 0.0))
            }
            outputs.file(output, listOfNotNull(input, truthPath?.toString())).use { it.write(fig.render().toByteArray(Charsets.UTF_8)) }
            // Over every sample with a reference: fusion eval scores a trial's scored rows only (BROAD's movement column).
            val stats = if (comparison.total.count > 0) String.format(Locale.ROOT, "; error vs %s over every sample: total RMS %.2f°, max %.2f°", refLabel, comparison.total.rms, comparison.total.max) else ""
            val markerNote = when {
                markers.isEmpty() -> ""
                outside > 0 -> "; ${markers.size} markers ($outside outside the replayed time, not drawn)"
                else -> "; ${markers.size} markers"
            }
            out.println("$output: ${names.joinToString("/")} over ${String.format(Locale.ROOT, "%.1f", tMax)} s$stats$markerNote")
        }
        return ExitCode.OK
    }
}
