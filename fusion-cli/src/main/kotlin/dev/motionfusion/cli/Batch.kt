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
    /** One input's job: the input, where its output goes, the arguments of its own run, and its rows' times (replay --align). */
    class Job(val input: String, val output: String, val args: List<String>, val rowTime: ((Long) -> Double)? = null)

    /**
     * The output of each input in [dir]: its file name without .csv/.csv.gz/.zip, then [extension].
     * Two inputs of the same name, and an output that is one of the inputs or lies inside one, are
     * usage errors before anything runs.
     */
    fun outputs(inputs: List<String>, dir: String, extension: String): List<String> {
        val folder = Path.of(dir)
        if (Files.exists(folder) && !Files.isDirectory(folder)) throw UsageException("with several inputs -o names a folder, and $dir is a file")
        if (!Files.exists(folder) && !dir.endsWith("/")) {
            throw UsageException("with several inputs -o names a folder: $dir does not exist; give $dir/ (ending in /) to have it made")
        }
        val names = inputs.map { stem(it) + extension }
        val clashes = inputs.indices.groupBy { names[it] }.filterValues { it.size > 1 }
        if (clashes.isNotEmpty()) {
            val (name, idx) = clashes.entries.first()
            throw UsageException("inputs ${idx.joinToString(" and ") { inputs[it] }} would both be written to ${folder.resolve(name)}; replay them into different folders or rename one")
        }
        val outs = names.map { folder.resolve(it).toString() }
        val check = Outputs()
        // The folder itself first: one inside an input is refused before it is made.
        check.check(folder.toString(), inputs)
        if (Files.isDirectory(folder)) for (o in outs) check.check(o, inputs)
        return outs
    }

    /** One input's outcome: its [value] when it succeeded, its exit [code] and what it wrote to standard error. */
    data class Outcome<T>(val input: String, val value: T?, val code: Int, val messages: String)

    /**
     * Runs [work] on each of [jobs] in parallel, each with its own stream for messages, and returns
     * their outcomes in input order, with the progress bar while they run. A job that throws fails
     * alone, with the exit code and message a whole run would have given ([Cli.failure]).
     */
    fun <J, T> map(jobs: List<J>, input: (J) -> String, work: (J, PrintStream) -> T): List<Outcome<T>> {
        val pool = Executors.newFixedThreadPool(maxOf(1, minOf(threads, jobs.size)))
        val results = arrayOfNulls<Outcome<T>>(jobs.size)
        val progress = Progress(err, command, jobs.size.toLong())
        try {
            val done = ExecutorCompletionService<Int>(pool)
            jobs.forEachIndexed { i, job ->
                done.submit {
                    val messages = ByteArrayOutputStream()
                    results[i] = PrintStream(messages, true, "UTF-8").use { e ->
                        try {
                            val v = work(job, e)
                            Outcome(input(job), v, ExitCode.OK, "")
                        } catch (t: Throwable) {
                            val (code, message) = if (t is Exited) t.code to null else Cli.failure(t, command) ?: throw t
                            message?.let { e.println("fusion: $it") }
                            Outcome<T>(input(job), null, code, "")
                        }
                    }.copy(messages = messages.toString("UTF-8").trim())
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
        return results.map { it!! }
    }

    /** Prints [describe] of each outcome (in input order; null: no line) and the summary; returns the worst exit code. */
    fun <T> summary(outcomes: List<Outcome<T>>, describe: (Outcome<T>) -> String?): Int {
        outcomes.forEach { r -> describe(r)?.let { err.println(it) } }
        val failed = outcomes.filter { it.code != ExitCode.OK }
        err.println(
            "fusion $command: ${outcomes.size} input${if (outcomes.size == 1) "" else "s"}: ${outcomes.size - failed.size} ok, ${failed.size} failed" +
                failed.joinToString("") { "\n  ${it.input}: exit ${it.code}: ${lastLine(it.messages)}" },
        )
        return outcomes.maxOfOrNull { it.code } ?: ExitCode.OK
    }

    /** Runs each job as its own run of the command (its own [Cli], so its own [Outputs]), then [summary]. */
    fun run(jobs: List<Job>, describe: (Outcome<Job>) -> String): Int {
        val outcomes = map(jobs, { it.input }) { job, e ->
            val code = PrintStream(ByteArrayOutputStream(), true, "UTF-8").use { o -> Cli(o, e, rowTime = job.rowTime).run(listOf(command) + job.args) }
            if (code != ExitCode.OK) throw Exited(code)
            job
        }
        return summary(outcomes.mapIndexed { i, r -> if (r.value == null) r.copy(value = jobs[i]) else r }, describe)
    }

    /** A run of the command that ended with [code], its message already given. */
    private class Exited(val code: Int) : RuntimeException()

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
