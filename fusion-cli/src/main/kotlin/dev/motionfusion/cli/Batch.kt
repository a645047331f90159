package dev.motionfusion.cli

import java.io.ByteArrayOutputStream
import java.io.PrintStream
import java.nio.file.Files
import java.nio.file.Path
import java.util.concurrent.ExecutorCompletionService
import java.util.concurrent.Executors

/**
 * Many inputs in one process: each input is one run of the command as if given alone (its own
 * [Cli], so its own [Outputs]: written aside, moved into place when that input succeeded, removed
 * when it failed), on a fixed pool of one thread per available core. One bad input does not stop
 * the others: its message and exit code go into its result line and the summary, and the exit code
 * of the whole run is the worst one.
 */
internal class Batch(private val command: String, private val err: PrintStream, private val threads: Int = Runtime.getRuntime().availableProcessors()) {
    /** One input's job: the input, where its output goes, and the arguments of its own run. */
    class Job(val input: String, val output: String, val args: List<String>)

    class Result(val job: Job, val code: Int, val messages: String)

    /**
     * The output of each input in [dir]: its file name without .csv/.csv.gz/.zip, then [extension].
     * Two inputs of the same name, and an output that is one of the inputs or lies inside one, are
     * usage errors before anything runs.
     */
    fun outputs(inputs: List<String>, dir: String, extension: String): List<String> {
        val folder = Path.of(dir)
        if (Files.exists(folder) && !Files.isDirectory(folder)) throw UsageException("with several inputs -o names a folder, and $dir is a file")
        val names = inputs.map { stem(it) + extension }
        val clashes = inputs.indices.groupBy { names[it] }.filterValues { it.size > 1 }
        if (clashes.isNotEmpty()) {
            val (name, idx) = clashes.entries.first()
            throw UsageException("inputs ${idx.joinToString(" and ") { inputs[it] }} would both be written to ${folder.resolve(name)}; replay them into different folders or rename one")
        }
        val outs = names.map { folder.resolve(it).toString() }
        val check = Outputs()
        for (o in outs) check.check(o, inputs)
        return outs
    }

    /** Runs [jobs] in parallel; prints one result line per input (in input order) and a summary; returns the worst exit code. */
    fun run(jobs: List<Job>, describe: (Result) -> String): Int {
        val pool = Executors.newFixedThreadPool(maxOf(1, minOf(threads, jobs.size)))
        val results = arrayOfNulls<Result>(jobs.size)
        val progress = Progress(err, command, jobs.size.toLong())
        try {
            val done = ExecutorCompletionService<Int>(pool)
            jobs.forEachIndexed { i, job ->
                done.submit {
                    val out = ByteArrayOutputStream()
                    val messages = ByteArrayOutputStream()
                    val code = PrintStream(out, true, "UTF-8").use { o ->
                        PrintStream(messages, true, "UTF-8").use { e -> Cli(o, e).run(listOf(command) + job.args) }
                    }
                    results[i] = Result(job, code, messages.toString("UTF-8").trim())
                    i
                }
            }
            repeat(jobs.size) { n ->
                done.take().get()
                progress.update(n + 1L)
            }
        } finally {
            pool.shutdownNow()
            progress.finish()
        }
        var worst = ExitCode.OK
        val failed = ArrayList<Result>()
        for (r in results) {
            r!!
            err.println(describe(r))
            if (r.code != ExitCode.OK) failed += r
            worst = maxOf(worst, r.code)
        }
        err.println(
            "fusion $command: ${jobs.size} inputs: ${jobs.size - failed.size} ok, ${failed.size} failed" +
                failed.joinToString("") { "\n  ${it.job.input}: exit ${it.code}: ${lastLine(it.messages)}" },
        )
        return worst
    }

    companion object {
        /** The file or folder name of [input] without .csv, .csv.gz or .zip. */
        fun stem(input: String): String {
            val name = Path.of(input).toAbsolutePath().normalize().fileName?.toString() ?: "input"
            return name.removeSuffix(".gz").removeSuffix(".csv").removeSuffix(".zip")
        }

        /** The last line of a run's messages (its error), without the "fusion: " prefix. */
        fun lastLine(messages: String): String = messages.lineSequence().lastOrNull { it.isNotBlank() }?.removePrefix("fusion: ") ?: ""
    }
}
