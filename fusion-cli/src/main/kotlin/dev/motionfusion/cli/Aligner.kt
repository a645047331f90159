package dev.motionfusion.cli

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.sync.ClockTimeline
import dev.motionfusion.core.sync.GyroAlignment
import java.io.PrintStream
import java.util.Locale
import kotlin.math.sqrt

/**
 * Recordings of several phones on the first one's clock (docs/SYNC.md): the one aligner of `fusion align` and of
 * `fusion replay --align`. For each input after the first it chooses the method (link, gyro, utc; auto: the best the
 * pair allows), the offset, and a function that puts any of the input's timestamps on the first input's clock.
 * Notes go to [err] as `fusion COMMAND: note: …`.
 */
internal class Aligner(private val err: PrintStream, private val command: String) {
    /** What an input offers to align by: its gyroscope's magnitudes, wall-clock anchor, clock exchanges and origin. */
    class Input(
        val name: String, val times: LongArray, val rates: DoubleArray, val utcNs: Long?, val link: String?, val timeline: ClockTimeline?,
        /** The timestamp that is t = 0 s in the input's own replay: its start anchor, else its first event. */
        val originNs: Long,
    )

    /**
     * One input on the first one's clock: [offsetNs] to add to its timestamps (link: at the middle of the input, [driftPpm]
     * after), [uncertaintyNs] the bound on every one of its timestamps so mapped (NaN: not known, the wall clocks),
     * [utcOffsetNs] the wall clocks' offset, [correlation] and [runnerUp] of the gyroscopes where they were asked.
     */
    class Aligned(
        val input: Input, val method: String, val offsetNs: Long, val driftPpm: Double, val uncertaintyNs: Double,
        val utcOffsetNs: Long?, val correlation: Double, val runnerUp: Double,
        /** False where the gyroscopes decided without a motion that singles one offset out: the offset is a guess. */
        val certain: Boolean = true,
        private val map: (Long) -> Long,
    ) {
        /** [timestampNs] of this input on the first input's clock, ns. */
        fun toReference(timestampNs: Long): Long = map(timestampNs)
    }

    /** The inputs aligned, the first as the reference; [ambiguous]: how many the gyroscopes were asked about and could not tell. */
    class Result(val aligned: List<Aligned>, val ambiguous: Int) {
        val reference: Input get() = aligned.first().input

        /** The CSV of `fusion align -o` (and of `fusion replay --align`'s alignment.csv). */
        fun csv(): String {
            val csv = StringBuilder("$CSV_HEADER\n")
            for (a in aligned) {
                val quoted = a.input.name.let { n -> if (n.any { it == ',' || it == '"' || it == '\n' }) "\"" + n.replace("\"", "\"\"") + "\"" else n }
                fun num(v: Double) = if (v.isNaN()) "" else "%.6f".format(Locale.ROOT, v)
                csv.append("$quoted,${a.method},${a.offsetNs},${num(a.driftPpm)},${if (a.uncertaintyNs.isNaN()) "" else Math.round(a.uncertaintyNs).toString()}," +
                    "${a.utcOffsetNs ?: ""},${num(a.correlation)},${num(a.runnerUp)}\n")
            }
            return csv.toString()
        }
    }

    /** Reads [inputs] (at least two) and aligns them by [method] (auto, link, gyro or utc); [maxLagS]: the gyroscopes' search range. */
    fun align(inputs: List<String>, o: Options, method: String, maxLagS: Double?): Result {
        require(inputs.size >= 2 && method in METHODS)
        val recordings = inputs.map { read(it, o) }
        val ref = recordings.first()
        val aligned = ArrayList<Aligned>()
        aligned += Aligned(ref, "reference", 0, 0.0, 0.0, if (ref.utcNs != null) 0 else null, Double.NaN, Double.NaN) { it }
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
                val lag = ((maxLagS ?: if (utc != null) 5.0 else 60.0) * 1e9).toLong()
                try {
                    GyroAlignment.align(ref.times, ref.rates, r.times, r.rates, maxLagNs = lag, expectedNs = utc ?: 0L, minOverlapNs = minOf(5_000_000_000L, overlapFloor(ref, r)))
                } catch (e: IllegalArgumentException) {
                    if (method == "gyro" || utc == null) throw DataFormatException(r.name, 0, 0, "${e.message}")
                    err.println("fusion $command: note: ${r.name}: ${e.message}; the wall clocks are used")
                    null
                }
            }
            // A peak the window cuts off, or one without a rival to stand above (a window under a second), proves nothing.
            val clear = found != null && found.correlation >= MIN_CORRELATION && !found.atSearchEdge &&
                !found.runnerUp.isNaN() && found.correlation - found.runnerUp >= MIN_MARGIN
            val used = when {
                method != "auto" -> method
                linked -> "link"
                clear -> "gyro"
                utc != null -> "utc"
                else -> "gyro"
            }
            if (found != null && !clear) {
                ambiguous++
                // The figures formatted apart: a name may hold a format directive.
                val figures = "correlation %.3f, its best rival %.3f".format(Locale.ROOT, found.correlation, found.runnerUp) +
                    if (found.atSearchEdge) ", the best at the edge of the --max-lag window" else if (found.runnerUp.isNaN()) ", no rival in a window this narrow" else ""
                err.println("fusion $command: note: ${r.name}: the gyroscopes show no shared motion that singles one offset out ($figures): " +
                    if (used == "utc") "the wall clocks are used" else "shake the phones together once, irregularly, while all record")
            }
            aligned += when (used) {
                "utc" -> Aligned(r, used, utc!!, Double.NaN, Double.NaN, utc, found?.correlation ?: Double.NaN, found?.runnerUp ?: Double.NaN) { it + utc }
                "gyro" -> {
                    val offset = found!!.offsetNs
                    // Measured within one sample period of the slower phone (docs/SYNC.md, "A shared motion"): that is the bound stated.
                    val period = maxOf(medianPeriod(ref.times), medianPeriod(r.times)).toDouble()
                    Aligned(r, used, offset, Double.NaN, period, utc, found.correlation, found.runnerUp, clear) { it + offset }
                }
                else -> {
                    // Both on the laptop's clock: r's time → the laptop's → ref's, anchor by anchor (the drift between them followed).
                    val ta = ref.timeline!!
                    val tb = r.timeline!!
                    val map = { t: Long -> ta.toPhone(tb.toLaptop(t)) }
                    val b = r.times[0] + (r.times.last() - r.times[0]) / 2
                    val a = map(b)
                    val later = b + 1_000_000_000L
                    val drift = ((map(later) - later) - (a - b)) / 1e3
                    // The bound on every timestamp of r: the largest sum of the two timelines' bounds over r's span.
                    var bound = 0.0
                    var t = r.times[0]
                    while (true) {
                        bound = maxOf(bound, ta.uncertaintyAt(map(t)) + tb.uncertaintyAt(t))
                        if (t == r.times.last()) break
                        t = minOf(r.times.last(), t + 1_000_000_000L)
                    }
                    Aligned(r, used, a - b, drift, bound, utc, Double.NaN, Double.NaN, map = map)
                }
            }
        }
        return Result(aligned, ambiguous)
    }

    /** Recordings shorter than 10 s may still align over half their length. */
    private fun overlapFloor(a: Input, b: Input): Long = maxOf(1_000_000_000L, minOf(a.times.last() - a.times[0], b.times.last() - b.times[0]) / 2)

    private fun medianPeriod(times: LongArray): Long {
        val d = LongArray(times.size - 1) { times[it + 1] - times[it] }
        d.sort()
        return d[d.size / 2]
    }

    private fun read(input: String, o: Options): Input = InputOptions.open(input, o, err, command).use { rec ->
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
                err.println("fusion $command: note: ${rec.name}: its clock exchanges are not used: ${e.message}")
                null
            }
        }
        // As the replay takes it: the start anchor, else the first event of any stream.
        val origin = rec.originNs ?: rec.events().use { e -> if (e.next()) e.timestampNs else times[0] }
        Input(rec.name, times.copyOf(n), rates.copyOf(n), utcNs, link.takeIf { timeline != null }, timeline, origin)
    }

    companion object {
        val METHODS = setOf("auto", "link", "gyro", "utc")

        const val CSV_HEADER = "input,method,offset_ns,drift_ppm,uncertainty_ns,utc_offset_ns,correlation,runner_up"

        /** A shared motion correlates at least this much at its offset (independent motions: about 0.6). */
        const val MIN_CORRELATION = 0.8

        /** ...and this much above its best rival (a shaken pair: about 0.2), else the offset is not singled out. */
        const val MIN_MARGIN = 0.1
    }
}
