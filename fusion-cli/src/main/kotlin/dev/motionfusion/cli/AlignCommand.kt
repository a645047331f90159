package dev.motionfusion.cli

import java.io.PrintStream
import java.util.Locale

/** `fusion align`: several recordings of one motion on the first one's clock (docs/SYNC.md). */
internal class AlignCommand(private val err: PrintStream, private val outputs: Outputs) : Command {
    override val name = "align"
    override val summary = "puts recordings of several phones on one clock: by a clock link, their wall clocks or a shared shake"
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
        |The table gives the method used, the offset, the bound (±) on the input's times so mapped
        |(link: the clock exchanges' largest over the input; gyro: one sample period of the slower
        |phone; utc: not known), the wall clocks' offset and their difference, and the correlation at
        |the offset beside the best one at least 0.5 s away. The gyroscopes
        |decide only with a correlation of at least 0.8 and 0.1 above that rival, at a peak inside
        |the --max-lag window; else the motion was not shared, or repeats (shake once, irregularly,
        |while all record), and without wall clocks to fall back on the run fails (exit 1).
        |  -o, --output FILE   also write input,method,offset_ns,drift_ppm,uncertainty_ns,utc_offset_ns,
        |                      correlation,runner_up as CSV
        |  --max-lag S         search range around the wall-clock offset (default 5 s; 60 s without one)
        |  --method M          auto, link, gyro or utc
        |
        |${InputOptions.HELP}""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val o = Options(args, setOf("-o", "--output", "--max-lag", "--method") + InputOptions.VALUED, emptySet())
        val inputs = o.positional
        if (inputs.size < 2) throw UsageException("align needs at least two INPUTs")
        val method = method(o.value("--method"), "--method")
        val maxLag = maxLag(o)
        val output = o.value("-o") ?: o.value("--output")
        output?.let { outputs.check(it, inputs) }
        val result = Aligner(err, name).align(inputs, o, method, maxLag)
        out.println("| input | method | offset (s) | drift (ppm) | ± (ms) | wall clocks (s) | correlation | runner-up |")
        out.println("|---|---|---|---|---|---|---|---|")
        for (a in result.aligned) {
            val reference = a.method == "reference"
            val row = listOf(
                a.input.name, a.method, if (reference) "0" else seconds(a.offsetNs),
                if (reference) "0" else if (a.driftPpm.isNaN()) "" else "%+.2f".format(Locale.ROOT, a.driftPpm),
                if (reference) "0" else if (a.uncertaintyNs.isNaN()) "" else "%.3f".format(Locale.ROOT, a.uncertaintyNs / 1e6),
                a.utcOffsetNs?.let { if (reference) "0" else seconds(it) } ?: "–",
                if (a.correlation.isNaN()) "" else "%.3f".format(Locale.ROOT, a.correlation),
                if (a.runnerUp.isNaN()) "" else "%.3f".format(Locale.ROOT, a.runnerUp),
            )
            out.println(row.joinToString(" | ", "| ", " |") { it.replace("|", "\\|") })
        }
        out.println("offset: add it to the input's timestamps to put them on ${result.reference.name}'s clock (link: at the middle of the input, its drift after)")
        if (output != null) {
            outputs.file(output, inputs).use { it.write(result.csv().toByteArray()) }
        }
        // An offset the gyroscopes guessed (gyro asked for, or auto with no wall clock to fall back on) is no result.
        return if (result.aligned.any { it.method == "gyro" && !it.certain }) ExitCode.DATA_ERROR else ExitCode.OK
    }

    private fun seconds(ns: Long) = "%.6f".format(Locale.ROOT, ns / 1e9)

    companion object {
        /** The method named by [option] ([value]; default auto), checked. */
        fun method(value: String?, option: String): String = (value ?: "auto").also {
            if (it !in Aligner.METHODS) throw UsageException("$option must be auto, link, gyro or utc, not '$it'")
        }

        /** --max-lag in seconds, checked (null: the default). */
        fun maxLag(o: Options): Double? = o.value("--max-lag")?.let { v ->
            v.toDoubleOrNull()?.takeIf { it.isFinite() && it > 0 && it <= 86_400 } ?: throw UsageException("--max-lag must be a number of seconds in (0, 86400], not '$v'")
        }
    }
}
