package dev.motionfusion.cli

import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.io.AsciiNumbers
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.replay.ErrorStatistics
import dev.motionfusion.core.replay.OrientationComparison
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.replay.Replayer
import dev.motionfusion.core.event.SessionStream
import java.io.BufferedOutputStream
import java.io.OutputStream
import java.io.PrintStream
import java.nio.file.Files
import java.util.Locale

/** `fusion compare`: the replayed Madgwick orientation against the phone's rotation vector. */
internal class CompareCommand(private val err: PrintStream, private val outputs: Outputs) : Command {
    override val name = "compare"
    override val summary = "Madgwick output vs the phone's rotation vector: difference over time and statistics"
    override val help = """
        |Usage: fusion compare INPUT [-o DIFF.csv] [--game] [--live] [filter settings]
        |
        |Replays INPUT (a session, or a Sensor Logger export with Orientation.csv) and compares
        |the filter's orientation with the phone's own fusion, TYPE_ROTATION_VECTOR (both
        |sensor → East-North-Up). Each rotation vector sample is compared at its own timestamp
        |with the filter's orientation interpolated between the gyroscope steps around it.
        |Angle difference e = q_madgwick ⊗ q_phone*: total angle, heading (about the vertical)
        |and inclination (tilt) part, in degrees, as in BROAD's metric.
        |
        |Prints count, mean, RMS, median, 95th percentile and maximum of each.
        |  -o, --output FILE    also write the difference over time: t_s,total_deg,heading_deg,inclination_deg
        |  --game               compare with TYPE_GAME_ROTATION_VECTOR instead; its yaw is arbitrary,
        |                       so the heading difference at the first compared sample is removed
        |  --live               compare the live orientation recorded by the app (orientation.csv)
        |                       instead of replaying
        |  --quiet              no notes on standard error (warnings and errors still)
        |
        |${FilterOptions.HELP}
        |${InputOptions.HELP}""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val o = Options(args, setOf("-o", "--output") + FilterOptions.VALUED + InputOptions.VALUED, setOf("--game", "--live", "--quiet") + FilterOptions.FLAGS)
        val input = o.positional.singleOrNull() ?: throw UsageException("compare needs one INPUT")
        FilterOptions.settings(o) // usage errors before the input is opened
        val refStream = if (o.has("--game")) SessionStream.GAME_ROTATION_VECTOR else SessionStream.ROTATION_VECTOR
        val live = o.has("--live")
        val output = o.value("-o") ?: o.value("--output")
        InputOptions.open(input, o, err, name).use { rec ->
            val settings = FilterOptions.settings(o, rec, err, name)
            if (refStream !in rec.streams) {
                val where = if (refStream == SessionStream.ROTATION_VECTOR) {
                    "the phone's own orientation (${refStream.fileName} in a session, Orientation.csv in a Sensor Logger export; a phyphox export's is not read)"
                } else {
                    "the phone's game rotation vector (${refStream.fileName} in a session; other apps' exports have none)"
                }
                throw DataFormatException(input, 0, 0, "$where is not in this ${rec.format.description}: nothing to compare with")
            }
            if (live && SessionStream.ORIENTATION !in rec.streams) throw DataFormatException(input, 0, 0, "no orientation.csv (live orientation) in this recording")
            var origin = rec.originNs
            val diff: OutputStream? = output?.let { BufferedOutputStream(outputs.file(it, listOf(input)), 1 shl 16) }
            val buf = ByteArray(256)
            diff?.write("t_s,total_deg,heading_deg,inclination_deg\n".toByteArray())
            // The game rotation vector, and the filter in 6D, have no north: their headings compare from a common start.
            val sixD = !live && settings.mode == FilterMode.IMU
            val comparison = OrientationComparison(removeInitialHeadingOffset = o.has("--game") || sixD) { t, total, heading, incl ->
                if (diff != null) {
                    var p = AsciiNumbers.fixed(buf, 0, Replayer.secondsBetween(origin ?: 0L, t), 9)
                    for (v in doubleArrayOf(total, heading, incl)) {
                        buf[p++] = ','.code.toByte()
                        p = AsciiNumbers.fixed(buf, p, v, 4)
                    }
                    buf[p++] = '\n'.code.toByte()
                    diff.write(buf, 0, p)
                }
            }
            val liveQ = DoubleArray(4)
            val listener = object : ReplayListener {
                override fun step(step: ReplayStep) {
                    if (origin == null) origin = step.timestampNs - (step.timeS * 1e9).toLong()
                    if (!live) comparison.estimate(step.timestampNs, step.orientation)
                }

                override fun reference(stream: SessionStream, timestampNs: Long, values: DoubleArray) {
                    if (stream == refStream) comparison.reference(timestampNs, values[3], values[0], values[1], values[2])
                    if (live && stream == SessionStream.ORIENTATION) {
                        values.copyInto(liveQ, 0, 0, 4)
                        comparison.estimate(timestampNs, liveQ)
                    }
                }
            }
            val progress = Progress(err, "compare", rec.metadata?.streams?.values?.sumOf { it.samples })
            diff.use { ReplayCommand.replay(rec, null, settings, null, listener, progress::update) }
            progress.finish()
            if (comparison.total.count == 0L) throw DataFormatException(input, 0, 0, "no ${refStream.fileName} sample falls between two filter steps")
            val what = if (live) "live orientation" else if (sixD) "Madgwick (replayed, 6D: heading from a common start)" else "Madgwick (replayed)"
            out.println("$what vs ${refStream.key} in ${rec.name}: ${comparison.total.count} samples")
            out.println(statsTable(listOf("total" to comparison.total, "heading" to comparison.heading, "inclination" to comparison.inclination)))
        }
        return ExitCode.OK
    }

    companion object {
        fun statsTable(rows: List<Pair<String, ErrorStatistics>>): String = buildString {
            appendLine("| difference (°) | mean | RMS | median | p95 | max |")
            appendLine("|---|---|---|---|---|---|")
            for ((n, s) in rows) {
                appendLine(String.format(Locale.ROOT, "| %s | %.2f | %.2f | %.2f | %.2f | %.2f |", n, s.mean, s.rms, s.percentile(0.5), s.percentile(0.95), s.max))
            }
        }.trimEnd()
    }
}
