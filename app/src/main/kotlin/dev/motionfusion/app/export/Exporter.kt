package dev.motionfusion.app.export

import dev.motionfusion.app.platform.SessionBusyException
import dev.motionfusion.app.platform.UnreadableSessionException
import android.content.ClipData
import android.content.ContentValues
import android.content.Context
import android.content.Intent
import android.net.Uri
import android.os.Build
import androidx.annotation.RequiresApi
import android.os.Environment
import android.provider.DocumentsContract
import android.provider.MediaStore
import kotlinx.coroutines.CancellationException
import dev.motionfusion.app.R
import dev.motionfusion.app.platform.NoiseTooShortException
import dev.motionfusion.app.platform.NothingToExportException
import dev.motionfusion.core.export.ExportOptions
import dev.motionfusion.core.export.Exports
import dev.motionfusion.core.export.NoiseConfigs
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.io.AtomicFiles
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.replay.HeadingTareSpec
import dev.motionfusion.core.session.SessionArchive
import dev.motionfusion.core.session.SessionReader
import java.io.File
import java.io.IOException
import java.io.OutputStream

/**
 * The three ways a session leaves app-private storage: Downloads through MediaStore (API 29+, no
 * permission), a document the user picks (ACTION_CREATE_DOCUMENT), and a share sheet with a
 * content:// URI from [ExportProvider]. Each writes one file as [ExportChoice] says ([write]): the
 * session format's zip ([SessionArchive.zip]: the folder's files inside a folder named after the
 * session), an export of fusion-core's [Exports] (what `fusion export` writes: replayed with the
 * filter settings and calibration the session recorded; EuRoC and Kalibr zipped) or a still
 * recording's noise configurations ([NoiseConfigs], as `fusion allan --configs`).
 * Blocking: call off the main thread. [Progress] gets the bytes of the session read so far and
 * their total; an exception it throws (a cancelled export's) stops the export, and what was begun
 * is removed (the zip aside, the pending Downloads entry, the picked document).
 */
internal object Exporter {
    /** How far an export is: (bytes of the session's files read, their total). */
    fun interface Progress {
        fun update(done: Long, total: Long)
    }

    private val NONE = Progress { _, _ -> }

    fun zipName(session: String): String = ExportKind.SESSION.fileName(session)

    /** What the exports name as their maker. */
    private const val GENERATOR = "Motion Fusion app"

    /**
     * Writes the session in [dir] as [choice] says to [out] (not closed); [scratch] holds the folder of a
     * zipped format while it is written. A session without what the format needs, or a still recording
     * too short for noise figures, fails with [NothingToExportException] / [NoiseTooShortException].
     */
    @Throws(IOException::class)
    fun write(dir: File, choice: ExportChoice, out: OutputStream, scratch: File, progress: Progress = NONE) {
        val kind = choice.kind
        if (kind == ExportKind.SESSION) {
            SessionArchive.zip(dir.toPath(), out, null, progress::update)
            return
        }
        scratch.mkdirs()
        try {
            Recording.open(dir.toPath()).use { rec ->
                // The replay's progress is in events read: their total is meta.json's per-stream count.
                val total = rec.metadata?.streams?.values?.sumOf { it.samples } ?: 0L
                val events: (Long) -> Unit = { n -> progress.update(n, maxOf(total, n)) }
                progress.update(0L, total)
                val name = kind.fileName(dir.name).removeSuffix(".zip")
                if (kind == ExportKind.NOISE) {
                    NoiseConfigs.writeZip(rec, GENERATOR, out, name, scratch.toPath(), events)
                } else {
                    val m = rec.metadata
                    val options = ExportOptions(
                        settings = m?.filterSettings ?: FilterSettings(),
                        calibration = m?.calibration?.takeIf { it.appliedInLiveFilter }?.calibration,
                        heading = if (choice.zeroHeading && kind.hasOrientation) HeadingTareSpec.at(null, 0.0) else null,
                        generator = GENERATOR,
                    )
                    Exports.writeZip(rec, kind.format!!, out, name, scratch.toPath(), options, events)
                }
            }
        } catch (e: DataFormatException) {
            // Without a file position: what the recording lacks (no gyroscope, too short), else a damaged file.
            throw when {
                e.line != 0L -> UnreadableSessionException("${dir.name}: ${e.message}", e)
                kind == ExportKind.NOISE -> NoiseTooShortException("${dir.name}: ${e.reason}", e)
                else -> NothingToExportException("${dir.name}: ${e.reason}", e)
            }
        }
    }

    /** Only a finished (or repaired) session leaves the app: never one being written. */
    @Throws(IOException::class)
    fun checkExportable(dir: File) {
        val complete = try {
            SessionReader.open(dir.toPath()).use { it.metadata.complete }
        } catch (e: Exception) {
            throw UnreadableSessionException("${dir.name} is not a readable session: ${e.message}", e)
        }
        if (!complete) throw SessionBusyException("${dir.name} is still being recorded")
    }

    /** Writes the export to [target] all-or-nothing (the project's [AtomicFiles]): a failed export leaves no partial file. */
    @Throws(IOException::class)
    fun writeZip(dir: File, target: File, choice: ExportChoice = ExportChoice(), progress: Progress = NONE) {
        checkExportable(dir)
        target.parentFile?.mkdirs()
        AtomicFiles().write(target.toPath()) { write(dir, choice, it, target.parentFile ?: File("."), progress) }
    }

    /** MediaStore.Downloads needs API 29; before that, Save as… covers it without a storage permission. */
    val downloadsAvailable: Boolean get() = Build.VERSION.SDK_INT >= 29

    /** Saves to Downloads: inserted pending, written, then published. Returns the display name. */
    @RequiresApi(29)
    @Throws(IOException::class)
    fun toDownloads(context: Context, dir: File, choice: ExportChoice = ExportChoice(), progress: Progress = NONE): String {
        check(downloadsAvailable) { "MediaStore.Downloads needs API 29" }
        checkExportable(dir)
        val resolver = context.contentResolver
        val name = choice.kind.fileName(dir.name)
        val values = ContentValues().apply {
            put(MediaStore.MediaColumns.DISPLAY_NAME, name)
            put(MediaStore.MediaColumns.MIME_TYPE, choice.kind.mime)
            put(MediaStore.MediaColumns.RELATIVE_PATH, Environment.DIRECTORY_DOWNLOADS)
            put(MediaStore.MediaColumns.IS_PENDING, 1)
        }
        val uri = resolver.insert(MediaStore.Downloads.EXTERNAL_CONTENT_URI, values)
            ?: throw IOException("Downloads refused the file")
        try {
            resolver.openOutputStream(uri, "w")?.use { write(dir, choice, it, scratch(context), progress) } ?: throw IOException("cannot open $name")
            resolver.update(uri, ContentValues().apply { put(MediaStore.MediaColumns.IS_PENDING, 0) }, null, null)
        } catch (e: Exception) {
            resolver.delete(uri, null, null)
            if (e is IOException || e is CancellationException) throw e
            throw IOException(e.message, e)
        }
        return name
    }

    /** Where the folder of a zipped format is written while it is zipped: the cache, never shared. */
    private fun scratch(context: Context) = File(context.cacheDir, "export-scratch")

    /** Writes the export into the document the user created. */
    @Throws(IOException::class)
    fun toDocument(context: Context, dir: File, document: Uri, choice: ExportChoice = ExportChoice(), progress: Progress = NONE) {
        checkExportable(dir)
        try {
            context.contentResolver.openOutputStream(document, "wt")?.use { write(dir, choice, it, scratch(context), progress) }
                ?: throw IOException("cannot open the document")
        } catch (e: Exception) {
            // The document the picker created holds a part of a zip: removed when its provider allows.
            runCatching { DocumentsContract.deleteDocument(context.contentResolver, document) }
            throw e
        }
    }

    /** Writes the export into the provider's folder and returns a chooser for ACTION_SEND with a read grant. */
    @Throws(IOException::class)
    fun shareIntent(context: Context, dir: File, choice: ExportChoice = ExportChoice(), progress: Progress = NONE): Intent {
        val exports = ExportProvider.exportDir(context)
        // The cache is for handing over, not for keeping: zips shared a day ago are gone.
        val dayAgo = System.currentTimeMillis() - 24L * 3600 * 1000
        exports.listFiles()?.filter { it.lastModified() < dayAgo }?.forEach { it.delete() }
        val file = File(exports, choice.kind.fileName(dir.name))
        checkExportable(dir)
        exports.mkdirs()
        AtomicFiles().write(file.toPath()) { write(dir, choice, it, scratch(context), progress) }
        val uri = ExportProvider.uriFor(context, file)
        val send = Intent(Intent.ACTION_SEND)
            .setType(choice.kind.mime)
            .putExtra(Intent.EXTRA_STREAM, uri)
            .putExtra(Intent.EXTRA_SUBJECT, dir.name)
            .addFlags(Intent.FLAG_GRANT_READ_URI_PERMISSION)
        send.clipData = ClipData.newRawUri(dir.name, uri)
        return Intent.createChooser(send, context.getString(R.string.export_share_title))
            .addFlags(Intent.FLAG_GRANT_READ_URI_PERMISSION)
    }
}
