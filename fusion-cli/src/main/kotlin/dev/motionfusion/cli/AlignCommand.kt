package dev.motionfusion.cli

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.sync.ClockTimeline
import dev.motionfusion.core.sync.GyroAlignment
import java.io.PrintStream
import java.util.Locale
import kotlin.math.sqrt

/** `fusion align`: several recordings of one motion on the first one's clock (docs/SYNC.md). */
internal class AlignCommand(private val err: PrintStream, private val outputs: Outputs) : Command {
    override val name = "align"
    override val summary = "puts recordings of several phones on one clock: by their wall clocks, refined by a shared shake"
    override val help = """
        |Usage: fusion align INPUT INPUT... [-o OFFSETS.csv] [--max-lag S] [--method auto|link|gyro|utc]
        |
        |Finds, for each INPUT after the first, the offset to add to its timestamps to put them on
        |the first INPUT's clock. INPUTs are anything 'fusion replay' reads that has a gyroscope.
        |  link  the clock exchanges of sessions that 'fusion listen' received on one computer: each
        |        phone's clock put on the computer's, typically within a millisecond; the drift between
        |        the phones and the uncertainty are given too
        |  utc   the wall clocks the recordings noted at their start (sessions of this app); as good
        |        as the phones' own time keeping, often tens of ms, sometimes seconds
        |  gyro  the recordings' gyroscopes: hold the phones together and shake them (or tap them
        |        together) once while all record; the magnitudes of their rotation rates are
        |        cross-correlated, within --max-lag around the wall-clock offset where both have one
        |  auto  link where both have it, else gyro where the shared motion singles one offset out,
        |        else utc (the default)
        |The table gives the method used, the offset, the wall clocks' offset and their difference,
        |and the correlation at the offset beside the best one at least 0.5 s away. The gyroscopes
        |decide only with a correlation of at least 0.8 and 0.1 above that rival; else the motion
        |was not shared, or repeats (shake once, irregularly, while all record).
        |  -o, --output FILE   also write input,method,offset_ns,drift_ppm,uncertainty_ns,utc_offset_ns,
        |                      correlation,runner_up as CSV
        |  --max-lag S         search range around the wall-clock offset (default 5 s; 60 s without one)
        |  --method M          auto, link, gyro or utc
        |
        |${InputOptions.HELP}""".trimMargin()

    private class Gyro(val name: String, val times: LongArray, val rates: DoubleArray, val utcNs: Long?, val link: String?, val timeline: ClockTimeline?)

    override fun run(args: List<String>, out: PrintStream): Int {
        val o = Options(args, setOf("-o", "--output", "--max-lag", "--method") + InputOptions.VALUED, emptySet())
        val inputs = o.positional
        if (inputs.size < 2) throw UsageException("align needs at least two INPUTs")
        val method = (o.value("--method") ?: "auto").also {
            if (it !in setOf("auto", "link", "gyro", "utc")) throw UsageException("--method must be auto, link, gyro or utc, not '$it'")
        }
        val maxLag = o.value("--max-lag")?.let { v ->
            v.toDoubleOrNull()?.takeIf { it.isFinite() && it > 0 && it <= 86_400 } ?: throw UsageException("--max-lag must be a number of seconds in (0, 86400], not '$v'")
        }
        val output = o.value("-o") ?: o.value("--output")
        output?.let { outputs.check(it, inputs) }
        val recordings = inputs.map { read(it, o) }
        val ref = recordings.first()
        val rows = ArrayList<List<String>>()
        val csv = StringBuilder("input,method,offset_ns,drift_ppm,uncertainty_ns,utc_offset_ns,correlation,runner_up\n")
        csv.append(csvRow(ref.name, "reference", 0, 0.0, 0.0, if (ref.utcNs != null) 0 else null, Double.NaN, Double.NaN))
        rows += listOf(ref.name, "reference", "0", "0", "0", if (ref.utcNs != null) "0" else "–", "", "")
        var ambiguous = 0
        for (r in recordings.drop(1)) {
            // Add to r's timestamps to reach ref's: the same wall-clock instant on both sensor clocks.
            val utc = if (ref.utcNs != null && r.utcNs != null) ref.utcNs - r.utcNs else null
            val linked = ref.link != null && ref.link == r.link
            if (method == "utc" && utc == null) throw DataFormatException(r.name, 0, 0, "no wall-clock anchor (only sessions of this app note one): use --method gyro")
            if (method == "link" && !linked) {
                throw DataFormatException(r.name, 0, 0, "no clock exchanges with the same laptop as ${ref.name} (sessions that fusion listen received on one computer have them): use --method gyro or utc")
            }
            val found = if (method == "utc" || method == "link" || (method == "auto" && linked)) {
                null
            } else {
                val lag = ((maxLag ?: if (utc != null) 5.0 else 60.0) * 1e9).toLong()
                try {
                    GyroAlignment.align(ref.times, ref.rates, r.times, r.rates, maxLagNs = lag, expectedNs = utc ?: 0L, minOverlapNs = minOf(5_000_000_000L, overlapFloor(ref, r)))
                } catch (e: IllegalArgumentException) {
                    if (method == "gyro" || utc == null) throw DataFormatException(r.name, 0, 0, "${e.message}")
                    err.println("fusion align: note: ${r.name}: ${e.message}; the wall clocks are used")
                    null
                }
            }
            val clear = found != null && found.correlation >= MIN_CORRELATION &&
                found.correlation - (found.runnerUp.takeIf { !it.isNaN() } ?: -1.0) >= MIN_MARGIN
            val used = when {
                method != "auto" -> method
                linked -> "link"
                clear -> "gyro"
                utc != null -> "utc"
                else -> "gyro"
            }
            if (found != null && !clear) {
                ambiguous++
                err.println("fusion align: note: ${r.name}: the gyroscopes show no shared motion that singles one offset out (correlation %.3f, its best rival %.3f): ".format(Locale.ROOT, found.correlation, found.runnerUp) +
                    if (used == "utc") "the wall clocks are used" else "shake the phones together once, irregularly, while all record")
            }
            var drift = Double.NaN
            var uncertainty = Double.NaN
            val offset = when (used) {
                "utc" -> utc!!
                "gyro" -> found!!.offsetNs
                else -> {
                    // Both on the laptop's clock: at the middle of r's recording, r's time → the laptop's → ref's.
                    val ta = ref.timeline!!
                    val tb = r.timeline!!
                    val b = r.times[0] + (r.times.last() - r.times[0]) / 2
                    val a = ta.toPhone(tb.toLaptop(b))
                    val later = b + 1_000_000_000L
                    drift = ((ta.toPhone(tb.toLaptop(later)) - later) - (a - b)) / 1e3
                    uncertainty = ta.uncertaintyAt(a) + tb.uncertaintyAt(b)
                    a - b
                }
            }
            rows += listOf(r.name, used, seconds(offset), if (drift.isNaN()) "" else "%+.2f".format(Locale.ROOT, drift),
                if (uncertainty.isNaN()) "" else "%.3f".format(Locale.ROOT, uncertainty / 1e6), utc?.let { seconds(it) } ?: "–",
                found?.let { "%.3f".format(Locale.ROOT, it.correlation) } ?: "", found?.runnerUp?.takeIf { !it.isNaN() }?.let { "%.3f".format(Locale.ROOT, it) } ?: "")
            csv.append(csvRow(r.name, used, offset, drift, uncertainty, utc, found?.correlation ?: Double.NaN, found?.runnerUp ?: Double.NaN))
        }
        out.println("| input | method | offset (s) | drift (ppm) | ± (ms) | wall clocks (s) | correlation | runner-up |")
        out.println("|---|---|---|---|---|---|---|---|")
        for (row in rows) out.println(row.joinToString(" | ", "| ", " |") { it.replace("|", "\\|") })
        out.println("offset: add it to the input's timestamps to put them on ${ref.name}'s clock (link: at the middle of the input, its drift after)")
        if (output != null) {
            outputs.file(output, inputs).use { it.write(csv.toString().toByteArray()) }
        }
        return if (method == "gyro" && ambiguous > 0) ExitCode.DATA_ERROR else ExitCode.OK
    }

    /** Recordings shorter than 10 s may still align over half their length. */
    private fun overlapFloor(a: Gyro, b: Gyro): Long = maxOf(1_000_000_000L, minOf(a.times.last() - a.times[0], b.times.last() - b.times[0]) / 2)

    private fun read(input: String, o: Options): Gyro = InputOptions.open(input, o, err, name).use { rec ->
        if (SessionStream.GYROSCOPE !in rec.streams) throw DataFormatException(input, 0, 0, "no gyroscope in this ${rec.format.description}: nothing to align by")
        var times = LongArray(1 shl 12)
        var rates = DoubleArray(1 shl 12)
        var n = 0
        rec.events(setOf(SessionStream.GYROSCOPE)).use { e ->
            while (e.next()) {
                if (e.stream != SessionStream.GYROSCOPE) continue
                val v = e.values
                val m = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
                if (!m.isFinite() || (n > 0 && e.timestampNs <= times[n - 1])) continue
                if (n == times.size) {
                    times = times.copyOf(n * 2)
                    rates = rates.copyOf(n * 2)
                }
                times[n] = e.timestampNs
                rates[n] = m
                n++
            }
        }
        if (n < 3) throw DataFormatException(input, 0, 0, "fewer than 3 gyroscope samples: nothing to align by")
        // The sensor clock's reading at the Unix epoch, from the anchor noted at the start.
        val utcNs = rec.metadata?.startAnchor?.let { it.elapsedRealtimeNs - it.wallClockMs * 1_000_000 }
        val exchanges = rec.clockExchanges()
        val link = rec.metadata?.clockLink?.takeIf { exchanges.size >= 2 }
        val timeline = link?.let {
            try {
                ClockTimeline(exchanges)
            } catch (e: IllegalArgumentException) {
                err.println("fusion align: note: ${rec.name}: its clock exchanges are not used: ${e.message}")
                null
            }
        }
        Gyro(rec.name, times.copyOf(n), rates.copyOf(n), utcNs, link.takeIf { timeline != null }, timeline)
    }

    private fun seconds(ns: Long) = "%.6f".format(Locale.ROOT, ns / 1e9)

    private fun csvRow(input: String, method: String, offset: Long, drift: Double, uncertainty: Double, utc: Long?, correlation: Double, runnerUp: Double): String {
        val quoted = if (input.any { it == ',' || it == '"' || it == '\n' }) "\"" + input.replace("\"", "\"\"") + "\"" else input
        fun num(v: Double) = if (v.isNaN()) "" else "%.6f".format(Locale.ROOT, v)
        return "$quoted,$method,$offset,${num(drift)},${if (uncertainty.isNaN()) "" else Math.round(uncertainty).toString()},${utc ?: ""},${num(correlation)},${num(runnerUp)}\n"
    }

    companion object {
        /** A shared motion correlates at least this much at its offset (independent motions: about 0.6). */
        const val MIN_CORRELATION = 0.8

        /** ...and this much above its best rival (a shaken pair: about 0.2), else the offset is not singled out. */
        const val MIN_MARGIN = 0.1
    }
}
