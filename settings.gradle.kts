// Android Studio project (Gradle). The build of record is the Maven reactor (pom.xml); these files
// describe the same modules, folders, dependencies, versions, test properties and JVM flags, and
// AndroidStudioProjectTest (app) fails when the two differ. The Gradle build runs on a CI with
// network access (.github/workflows/gradle.yml); the machines of the Maven build reach no Gradle
// distribution and no Android Gradle Plugin.
pluginManagement {
    repositories {
        google {
            content {
                includeGroupByRegex("com\\.android.*")
                includeGroupByRegex("com\\.google.*")
                includeGroupByRegex("androidx.*")
            }
        }
        mavenCentral()
        gradlePluginPortal()
    }
    // The release build's R8: Kotlin 2.4's metadata needs a newer R8 than the one AGP 8.7 bundles
    // (gradle/compatibility.tsv), so the R8 of the Maven build (root pom.xml, r8.version) goes here,
    // where R8's documentation puts a replacement for AGP's own: on the class path of the settings'
    // plugin resolution, ahead of the plugins it loads. Catalogs are not read in this block.
    buildscript {
        repositories {
            mavenCentral()
        }
        dependencies {
            classpath("com.android.tools:r8:9.5.28")
        }
    }
}

plugins {
    // Downloads the JDK of jvmToolchain(17) where the machine has another one (Android Studio's bundled JDK 21).
    id("org.gradle.toolchains.foojay-resolver-convention") version "0.9.0"
}

dependencyResolutionManagement {
    repositoriesMode.set(RepositoriesMode.FAIL_ON_PROJECT_REPOS)
    repositories {
        google()
        mavenCentral()
        // gummy-bears-api-26 (the API-level guard's signature) is published without a POM; Gradle takes a
        // module without metadata only from a repository that says to look for the artifact itself.
        exclusiveContent {
            forRepository {
                maven {
                    name = "MavenCentralArtifactsOnly"
                    url = uri("https://repo.maven.apache.org/maven2/")
                    metadataSources {
                        artifact()
                    }
                }
            }
            filter {
                includeModule("com.toasttab.android", "gummy-bears-api-26")
            }
        }
    }
}

rootProject.name = "motion-fusion"

// fusion-bench (JMH) depends on the app module's recording classes, which Gradle does not offer to
// a JVM module: run it with Maven. android-libs and android-test-libs are the Maven build's way of
// resolving AARs; Gradle resolves them itself from the app's dependencies.
include(":fusion-core")
include(":fusion-stream")
include(":fusion-cli")
include(":app")
