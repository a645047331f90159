/*
 * The reader of sessions (docs/SESSION_FORMAT.md): a folder or its zip export. Streams are read
 * lazily and merged by timestamp; memory is constant for any length.
 */
package dev.motionfusion.core.session

import dev.motionfusion.core.io.ByteCsvReader
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.FieldError
import java.io.Closeable
import java.io.IOException
import java.io.InputStream
import java.nio.charset.StandardCharsets
import java.nio.file.Files
import java.nio.file.Path
import java.util.stream.Collectors
import java.util.zip.ZipException
import java.util.zip.ZipFile

/**
 * An open session. [metadata] is read at once; the streams when [events] or [stream] is called
 * (each call opens its files anew, so a session can be read several times).
 */
public class SessionReader private constructor(
    private val files: SessionFiles,
    /** The metadata of meta.json. */
    public val metadata: SessionMetadata,
) : Closeable {

    /** The session's name: folder or zip name. */
    public val name: String get() = files.name

    /** The streams that have a file in the session. */
    public val streams: Set<SessionStream> =
        SessionStream.entries.filterTo(java.util.EnumSet.noneOf(SessionStream::class.java)) { files.exists(it.fileName) }

    /**
     * Events of [which] streams (default: all present) merged in time order. In a session that
     * was not closed ("complete": false) an unterminated last line of a file is skipped as cut
     * off by the interruption; in a complete session it is read like any other.
     */
    public fun events(which: Set<SessionStream> = streams): SessionEvents =
        MergedEvents(which.filter { it in streams }.map { cursor(it) })

    /** The events of one stream in file order. */
    public fun stream(s: SessionStream): SessionEvents {
        require(s in streams) { "$name has no ${s.fileName}" }
        return MergedEvents(listOf(cursor(s)))
    }

    private fun cursor(s: SessionStream): StreamCursor =
        SessionCsvCursor(s, ByteCsvReader(files.open(s.fileName), files.displayName(s.fileName)), skipCutLastLine = !metadata.complete)

    override fun close(): Unit = files.close()

    public companion object {
        /**
         * Opens the session folder or zip at [path]. In a zip, the session may sit at the root or
         * in one folder (meta.json locates it).
         * @throws DataFormatException for a missing or malformed meta.json or a broken zip.
         */
        @JvmStatic
        public fun open(path: Path): SessionReader {
            val files = SessionFiles.open(path)
            try {
                if (!files.exists(SessionMetadata.FILE_NAME)) {
                    throw DataFormatException(files.displayName(SessionMetadata.FILE_NAME), 0, 0, "missing: not a session (no meta.json)")
                }
                val text = try {
                    files.open(SessionMetadata.FILE_NAME).use { String(it.readBytes(), StandardCharsets.UTF_8) }
                } catch (e: ZipException) {
                    throw DataFormatException(files.displayName(SessionMetadata.FILE_NAME), 0, 0, "corrupt compressed data: ${e.message}", e)
                } catch (e: java.io.EOFException) {
                    throw DataFormatException(files.displayName(SessionMetadata.FILE_NAME), 0, 0, "compressed data ends early: ${e.message}", e)
                }
                return SessionReader(files, MetadataJson.parse(text, files.displayName(SessionMetadata.FILE_NAME)))
            } catch (e: Throwable) {
                files.close()
                throw e
            }
        }

        /** True when [path] is a folder with meta.json or a zip holding one. */
        @JvmStatic
        public fun isSession(path: Path): Boolean = try {
            SessionFiles.open(path).use { it.exists(SessionMetadata.FILE_NAME) }
        } catch (e: IOException) {
            false
        } catch (e: DataFormatException) {
            false
        }
    }
}

/** The files of a session: a folder or a zip (at its root or in one sub-folder). */
internal abstract class SessionFiles : Closeable {
    abstract val name: String
    abstract fun exists(file: String): Boolean
    abstract fun open(file: String): InputStream
    abstract fun displayName(file: String): String
    abstract fun list(): List<String>

    private class Folder(private val dir: Path) : SessionFiles() {
        override val name: String = dir.fileName?.toString() ?: dir.toString()
        override fun exists(file: String) = Files.isRegularFile(dir.resolve(file))
        override fun open(file: String): InputStream = Files.newInputStream(dir.resolve(file))
        override fun displayName(file: String) = dir.resolve(file).toString()
        override fun list(): List<String> = Files.list(dir).use { s -> s.map { it.fileName.toString() }.collect(Collectors.toList()) }
        override fun close() {}
    }

    private class Zip(private val path: Path) : SessionFiles() {
        private val zip = try {
            ZipFile(path.toFile())
        } catch (e: ZipException) {
            throw DataFormatException(path.toString(), 0, 0, "not a readable zip file: ${e.message}")
        }
        private val prefix: String
        override val name: String = path.fileName.toString()

        init {
            val metas = zip.entries().asSequence().map { it.name }.filter { it == SessionMetadata.FILE_NAME || it.endsWith("/" + SessionMetadata.FILE_NAME) }.toList()
            prefix = metas.minByOrNull { it.length }?.removeSuffix(SessionMetadata.FILE_NAME) ?: ""
        }

        override fun exists(file: String) = zip.getEntry(prefix + file)?.isDirectory == false
        override fun open(file: String): InputStream = zip.getEntry(prefix + file)?.let { zip.getInputStream(it) }
            ?: throw java.nio.file.NoSuchFileException(displayName(file))
        override fun displayName(file: String) = "$path!/$prefix$file"
        override fun list(): List<String> = zip.entries().asSequence().map { it.name }.filter { it.startsWith(prefix) && !it.endsWith("/") }
            .map { it.removePrefix(prefix) }.filter { '/' !in it }.toList()
        override fun close() = zip.close()
    }

    companion object {
        fun open(path: Path): SessionFiles = when {
            Files.isDirectory(path) -> Folder(path)
            Files.isRegularFile(path) -> Zip(path)
            else -> throw java.nio.file.NoSuchFileException(path.toString())
        }
    }
}

/** One session CSV: header checked by column name, rows parsed from bytes. */
internal class SessionCsvCursor(
    override val stream: SessionStream,
    private val csv: ByteCsvReader,
    private val skipCutLastLine: Boolean,
) : StreamCursor {
    override var timestampNs: Long = 0L
        private set
    override val values: DoubleArray = DoubleArray(stream.valueCount)
    override var accuracy: Int = SessionEvents.NO_ACCURACY
        private set

    private val timeIndex: Int
    private val valueIndex = IntArray(stream.valueCount)
    private val accuracyIndex: Int
    private val fieldsNeeded: Int

    init {
        try {
            if (!csv.nextLine()) throw DataFormatException(csv.sourceName, 1, 0, "empty file: expected the header ${stream.header}")
            val names = (0 until csv.count).map { csv.text(it).trim().removePrefix("\uFEFF") }
            fun find(name: String): Int {
                val i = names.indexOf(name)
                if (i < 0) throw DataFormatException(csv.sourceName, csv.lineNumber, 1, "header lacks column '$name'; expected ${stream.header}")
                return i
            }
            timeIndex = find(SessionStream.TIMESTAMP_COLUMN)
            for (k in valueIndex.indices) valueIndex[k] = find(stream.valueColumns[k])
            accuracyIndex = if (stream.hasAccuracy) find(SessionStream.ACCURACY_COLUMN) else -1
            fieldsNeeded = maxOf(timeIndex, accuracyIndex, valueIndex.maxOrNull() ?: 0) + 1
        } catch (e: Throwable) {
            csv.close()
            throw e
        }
    }

    override fun next(): Boolean {
        if (!csv.nextLine()) return false
        if (skipCutLastLine && !csv.endedWithNewline) return false
        if (csv.count < fieldsNeeded) {
            throw csv.error(csv.count, "row has ${csv.count} fields, expected ${stream.header.count { it == ',' } + 1} (${stream.header})")
        }
        var field = timeIndex
        try {
            timestampNs = csv.parseLong(field)
            for (k in valueIndex.indices) {
                field = valueIndex[k]
                values[k] = csv.parseDouble(field, emptyIsNaN = stream == SessionStream.ROTATION_VECTOR && k == 4)
            }
            if (accuracyIndex >= 0) {
                field = accuracyIndex
                val a = csv.parseLong(field)
                if (a < -1 || a > 3) throw FieldError("accuracy $a is not one of -1, 0, 1, 2, 3")
                accuracy = a.toInt()
            }
        } catch (e: FieldError) {
            throw csv.error(field, "column ${columnName(field)}: ${e.reason}")
        }
        return true
    }

    private fun columnName(field: Int): String = when (field) {
        timeIndex -> SessionStream.TIMESTAMP_COLUMN
        accuracyIndex -> SessionStream.ACCURACY_COLUMN
        else -> stream.valueColumns.getOrElse(valueIndex.indexOf(field)) { "?" }
    }

    override fun close(): Unit = csv.close()
}
